#!/usr/bin/env bash
# The viewer's end-to-end check (CTest `viewer_xvfb`), on any Vulkan device, lavapipe included:
#   1. train a tiny model with the command line (seconds, not quality: any field will do);
#   2. render test camera $CAMERA with `vknerf render` (the reference PNG);
#   3. run vknerf-view under Xvfb on the same camera for 3 frames and take its screenshot;
#   4. compare the two PNGs;
#   5. the same for --train: the viewer trains two steps, shows the model, saves it; the CLI renders it;
#   6. a screenshot onto the model is refused and the model kept.
# The viewer renders through Model::recordRender into a storage image and presents via the X11 WSI, so
# this covers window, swapchain, adoption, the render, the blit and the readback.
#
# Threshold: both images come from the same kernels for the same camera; the CLI rounds its floats
# to 8 bits on the host, the viewer's storage image (R8G8B8A8_UNORM) is rounded by the device. Each
# channel may therefore differ by one level, so the mean absolute difference is below 1 level. A wrong
# camera, channel order, resolution or a stale image gives far more; the neighbouring test camera's
# render must differ by more than MIN_OTHER so that a pass means the comparison can tell views apart.
#
# Usage: check_viewer.sh BUILD_DIR SCENE. Exit 0 pass, 1 fail, 77 skipped (no xvfb-run).
# Run it with VKNERF_VALIDATION=1 (CTest does): any validation message fails it.
set -euo pipefail
BUILD=${1:?usage: check_viewer.sh BUILD_DIR SCENE}
SCENE=${2:?usage: check_viewer.sh BUILD_DIR SCENE}
CAMERA=2
MAX_MEAN=1.0   # levels of 255: 8-bit rounding only
MIN_OTHER=3.0  # levels of 255: the next camera's view must be at least this far away

if ! command -v xvfb-run >/dev/null 2>&1; then
  echo "SKIP: xvfb-run not found (install xvfb and xauth); the viewer check needs an X server"
  exit 77
fi
for exe in vknerf vknerf-view vknerf-png-diff; do
  [ -x "$BUILD/$exe" ] || { echo "FAIL: $BUILD/$exe is not built"; exit 1; }
done

WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

run() {  # run a command, keep its output, fail on a non-zero exit or any validation message
  local log="$WORK/$1.log"; shift
  if ! "$@" >"$log" 2>&1; then
    cat "$log"; echo "FAIL: $* exited non-zero"; exit 1
  fi
  if grep -Eq "validation (warning|error)|validation message" "$log"; then
    cat "$log"; echo "FAIL: validation messages from: $*"; exit 1
  fi
}

start=$SECONDS
run train "$BUILD/vknerf" train "$SCENE" --config vanilla --steps 20 --downscale 4 --width 32 --depth 2 --coarse 16 --fine 16 \
  --rays 256 --save-every 0 -o "$WORK/tiny.vknerf"
run render "$BUILD/vknerf" render "$WORK/tiny.vknerf" "$SCENE" --downscale 4 --limit $((CAMERA + 2)) -o "$WORK/cli"
run viewer xvfb-run -a -s "-screen 0 640x480x24" "$BUILD/vknerf-view" "$WORK/tiny.vknerf" --scene "$SCENE" \
  --downscale 4 --camera "$CAMERA" --frames 3 --screenshot "$WORK/shot.png"
grep "frame time" "$WORK/viewer.log"

ref=$(printf "%s/cli/rgb_%04d.png" "$WORK" "$CAMERA")
other=$(printf "%s/cli/rgb_%04d.png" "$WORK" $((CAMERA + 1)))
"$BUILD/vknerf-png-diff" "$WORK/shot.png" "$ref" --max-mean "$MAX_MEAN"
"$BUILD/vknerf-png-diff" "$WORK/shot.png" "$other" --min-mean "$MIN_OTHER"

# --train: two frames of one training step each; the last frame shows the model the viewer then saves,
# so the CLI's render of the saved checkpoint must match the screenshot the same way.
run viewer_train xvfb-run -a -s "-screen 0 640x480x24" "$BUILD/vknerf-view" "$WORK/trained.vknerf" --train "$SCENE" \
  --downscale 4 --frames 2 --steps-per-frame 1 --screenshot "$WORK/train_shot.png"
grep "frame time" "$WORK/viewer_train.log"
run render_trained "$BUILD/vknerf" render "$WORK/trained.vknerf" "$SCENE" --downscale 4 --limit 1 -o "$WORK/cli_trained"
"$BUILD/vknerf-png-diff" "$WORK/train_shot.png" "$WORK/cli_trained/rgb_0000.png" --max-mean "$MAX_MEAN"
# A screenshot onto the model (through a symlink) is refused before any window opens; the model is kept.
cp "$WORK/tiny.vknerf" "$WORK/tiny.copy"
ln -s "$WORK/tiny.vknerf" "$WORK/link.png"
set +e
"$BUILD/vknerf-view" "$WORK/tiny.vknerf" --frames 1 --screenshot "$WORK/link.png" >"$WORK/clash.log" 2>&1
code=$?
set -e
if [ $code -ne 2 ] || ! grep -q "is the model" "$WORK/clash.log" || ! cmp -s "$WORK/tiny.vknerf" "$WORK/tiny.copy"; then
  cat "$WORK/clash.log"; echo "FAIL: --screenshot onto the model: exit $code (2 due), the model must be kept"; exit 1
fi
echo "PASS: viewer screenshots match vknerf render (loaded model, test camera $CAMERA; --train, camera 0) in $((SECONDS - start)) s"
