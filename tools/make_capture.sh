#!/usr/bin/env bash
# Renders the unbounded, lens-distorted capture (tools/make_capture.py) with Debian's Blender, headless, Cycles
# on the CPU; warps it into the dataset (tools/warp_capture.py), with an undistorted twin; checks both
# (tools/check_capture.py). At the defaults (45 views, 270x480, wide renders 446x782 at 12 spp) rendering took
# 9.2 CPU-minutes (under 5 minutes on 2 free cores; 22 minutes on a shared, loaded machine), the warp 1.7.
# Usage: tools/make_capture.sh [output folder, default /work/data/capture] [extra make_capture.py options...]
#   tools/make_capture.sh /work/data/wall --scene wall: objects on a patterned wall (50 views, 7 held out; 20 minutes
#   of rendering and 5-12 of warping on the shared machine). Regenerated with the defaults, the unbounded capture
#   took 24 minutes of rendering and 4 of warping there.
# Writes <out>/ (distorted: transforms*.json, sparse/0/*.bin, images/), <out>/wide/ (the renders and
# render.json, kept so the warp can be redone) and <out>-pinhole/ (the same views without distortion).
# Nothing here is committed: regenerate it (the renders are seeded, so the same command gives the same data).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT="${1:-/work/data/capture}"
shift || true
source tools/scenegen/need_blender.sh
rm -rf "$OUT/wide" "$OUT/images" "$OUT/sparse" "$OUT-pinhole"
blender -b --factory-startup -P tools/make_capture.py -- --out "$OUT" "$@"
/usr/bin/python3 tools/warp_capture.py "$OUT" --pinhole "$OUT-pinhole"
/usr/bin/python3 tools/check_capture.py "$OUT"
/usr/bin/python3 tools/check_capture.py "$OUT-pinhole"
