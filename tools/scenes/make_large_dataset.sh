#!/usr/bin/env bash
# The sample scene at nerf_synthetic's native size, for the large-dataset memory path: 800x800, 100 training
# + 20 test views (64 million training pixels), rendered by make_scene.py and checked by
# check_scene.py. 16 samples per pixel keep it to ~6 s of CPU per view (measured: 3.5 s at 8 spp, 6 s at
# 16, Blender 3.4.1, 2 threads); the whole set took 12.3 CPU-minutes (about 6 minutes on 2 free cores, 17 on a
# loaded machine). The noise is mild. Not committed.
# Usage: tools/scenes/make_large_dataset.sh OUTPUT_FOLDER [extra make_scene.py options...]
set -euo pipefail
cd "$(dirname "$0")/../.."
if [ $# -lt 1 ]; then echo "usage: $0 OUTPUT_FOLDER [make_scene.py options...]" >&2; exit 2; fi
OUT=$1
shift
source tools/scenes/need_blender.sh
rm -rf "$OUT/train" "$OUT/test"
blender_module make_scene --out "$OUT" --size 800 --train 100 --test 20 --samples 16 "$@"
/usr/bin/python3 -m tools.scenes.check_scene "$OUT" --size 800
