#!/usr/bin/env bash
# The sample scene at nerf_synthetic's native size, for the large-dataset memory path: 800x800, 100 training
# + 20 test views (64 million training pixels), rendered by tools/make_scene.py and checked by
# tools/check_scene.py. 16 samples per pixel keep it to ~6 s of CPU per view (measured: 3.5 s at 8 spp, 6 s at
# 16, Blender 3.4.1, 2 threads); the whole set took 12.3 CPU-minutes (about 6 minutes on 2 free cores, 17 on a
# loaded machine). The noise is mild. Not committed.
# Usage: tools/make_large_dataset.sh [output folder, default /work/data/large] [extra make_scene.py options...]
set -euo pipefail
cd "$(dirname "$0")/.."
OUT="${1:-/work/data/large}"
shift || true
source tools/scenegen/need_blender.sh
rm -rf "$OUT/train" "$OUT/test"
blender -b --factory-startup -P tools/make_scene.py -- --out "$OUT" --size 800 --train 100 --test 20 --samples 16 "$@"
/usr/bin/python3 tools/check_scene.py "$OUT" --size 800
