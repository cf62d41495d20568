#!/usr/bin/env bash
# Renders the forward-facing capture (make_ffwd_capture.py: a fern-like plant before a room, 20 views
# at 1008x756) with Debian's Blender, headless, Cycles on the CPU; writes it as LLFF ships its scenes and as a
# transforms.json twin, and checks that both describe the same cameras (llff_capture.py).
# Usage: tools/scenes/make_ffwd_capture.sh OUTPUT_FOLDER [extra make_ffwd_capture.py options...]
# Writes <out>/ (poses_bounds.npy, images/, images_2/, images_4/, and render/: the renders and render.json,
# kept so the layouts can be rewritten without rendering) and <out>-json/ (transforms*.json, images/ at 504x378).
# Nothing here is committed: regenerate it (the renders are seeded, so the same command gives the same data).
set -euo pipefail
cd "$(dirname "$0")/../.."
if [ $# -lt 1 ]; then echo "usage: $0 OUTPUT_FOLDER [make_ffwd_capture.py options...]" >&2; exit 2; fi
OUT=$1
shift
source tools/scenes/need_blender.sh
rm -rf "$OUT/render" "$OUT/images" "$OUT/images_2" "$OUT/images_4" "$OUT/poses_bounds.npy" "$OUT-json"
blender_module make_ffwd_capture --out "$OUT" "$@"
/usr/bin/python3 -m tools.scenes.llff_capture "$OUT" --json "$OUT-json"
