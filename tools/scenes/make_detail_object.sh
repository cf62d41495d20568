#!/usr/bin/env bash
# Renders the detailed test object (make_detail_object.py: a pavilion of many small parts, thin rods, wires,
# a lattice, metals and fine procedural textures) with Debian's Blender, headless, Cycles on the CPU, in
# nerf_synthetic layout: by default 800x800, 100 training views on the upper hemisphere and 200 test views
# on a circle at 30 degrees, 16 samples per pixel. Then checks it with check_scene.py.
# CPU time, measured with Blender 3.4.1, 2 threads, niced on a busy 2-core machine: ~4 s to start and build
# the object, then per view under 1 s at 96x96 / 4 spp, 5 s at 800x800 / 4 spp and 12.7 s at 800x800 / 16 spp
# (one training view at 18 degrees and one test view at 30; about 2.4 s of each view is fixed: the world's
# importance map, the BVH and saving the PNG; the rest grows with the samples, ~0.64 s per sample per
# view at 800x800). Extrapolated, not measured: the default 300 views at 800x800 / 16 spp take ~65
# CPU-minutes (~30 minutes on 2 free cores). 16 spp leaves visible grain on the glossy parts; more --samples
# cost ~0.64 CPU-s per sample per view. Not committed.
# Usage: tools/scenes/make_detail_object.sh OUTPUT_FOLDER [extra make_detail_object.py options...]
#   e.g. tools/scenes/make_detail_object.sh /tmp/detail_tiny --size 96 --train 3 --test 2 --samples 4
#   --test-stride 8 renders only every 8th of the 200 test views (the 25 held out in docs/performance.md),
#   with the same training cameras: 125 views, about 40% of the time.
set -euo pipefail
cd "$(dirname "$0")/../.."
if [ $# -lt 1 ]; then echo "usage: $0 OUTPUT_FOLDER [make_detail_object.py options...]" >&2; exit 2; fi
OUT=$1
shift
# check_scene needs the image size: the last --size given, else make_detail_object.py's default.
SIZE=800
args=("$@")
for ((i = 0; i < ${#args[@]}; i++)); do
  case ${args[i]} in
    --size) SIZE=${args[i + 1]:-$SIZE} ;;
    --size=*) SIZE=${args[i]#--size=} ;;
  esac
done
source tools/scenes/need_blender.sh
rm -rf "$OUT/train" "$OUT/test"
blender_module make_detail_object --out "$OUT" "$@"
# --probe: the gold sphere's centre (make_detail_object.py: PROBE); --radius: its RADIUS.
/usr/bin/python3 -m tools.scenes.check_scene "$OUT" --size "$SIZE" --radius 4 --probe 0 0 1.02
