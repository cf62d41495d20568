#!/usr/bin/env bash
# Renders the forward-facing capture (tools/make_ffwd_capture.py: a fern-like plant before a room, 20 views
# at 1008x756) with Debian's Blender, headless, Cycles on the CPU; writes it as LLFF ships its scenes and as a
# transforms.json twin, and checks that both describe the same cameras (tools/llff_capture.py).
# Usage: tools/make_ffwd_capture.sh [output folder, default /work/data/ffwd] [extra make_ffwd_capture.py options...]
# Writes <out>/ (poses_bounds.npy, images/, images_2/, images_4/, and render/: the renders and render.json,
# kept so the layouts can be rewritten without rendering) and <out>-json/ (transforms*.json, images/ at 504x378).
# Nothing here is committed: regenerate it (the renders are seeded, so the same command gives the same data).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT="${1:-/work/data/ffwd}"
shift || true
source tools/scenegen/need_blender.sh
rm -rf "$OUT/render" "$OUT/images" "$OUT/images_2" "$OUT/images_4" "$OUT/poses_bounds.npy" "$OUT-json"
blender -b --factory-startup -P tools/make_ffwd_capture.py -- --out "$OUT" "$@"
/usr/bin/python3 tools/llff_capture.py "$OUT" --json "$OUT-json"
