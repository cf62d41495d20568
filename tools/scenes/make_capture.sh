#!/usr/bin/env bash
# Renders the unbounded, lens-distorted capture (make_capture.py) with Debian's Blender, headless, Cycles
# on the CPU; warps it into the dataset (warp_capture.py), with an undistorted twin; checks both
# (check_capture.py). At the defaults (45 views, 270x480, wide renders 446x782 at 12 spp) rendering took
# 9.2 CPU-minutes (under 5 minutes on 2 free cores; 22 minutes on a shared, loaded machine), the warp 1.7.
# Usage: tools/scenes/make_capture.sh OUTPUT_FOLDER [extra make_capture.py options...] (a relative folder is
# taken from the repository root)
#   tools/scenes/make_capture.sh /tmp/wall --scene wall: objects on a patterned wall (50 views, 7 held out; 20 minutes
#   of rendering and 5-12 of warping on the shared machine). Regenerated with the defaults, the unbounded capture
#   took 24 minutes of rendering and 4 of warping there.
# Writes <out>/ (distorted: transforms*.json, sparse/0/*.bin, images/), <out>/wide/ (the renders and
# render.json, kept so the warp can be redone) and <out>-pinhole/ (the same views without distortion).
# Nothing here is committed: regenerate it (the renders are seeded, so the same command gives the same data).
set -euo pipefail
cd "$(dirname "$0")/../.."
if [ $# -lt 1 ]; then echo "usage: $0 OUTPUT_FOLDER [make_capture.py options...]" >&2; exit 2; fi
OUT=$1
shift
source tools/scenes/need_blender.sh
rm -rf "$OUT/wide" "$OUT/images" "$OUT/sparse" "$OUT-pinhole"
blender_module make_capture --out "$OUT" "$@"
/usr/bin/python3 -m tools.scenes.warp_capture "$OUT" --pinhole "$OUT-pinhole"
/usr/bin/python3 -m tools.scenes.check_capture "$OUT"
/usr/bin/python3 -m tools.scenes.check_capture "$OUT-pinhole"
