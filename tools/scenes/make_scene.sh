#!/usr/bin/env bash
# Regenerates the shipped sample scene (assets/tabletop) with Debian's Blender, headless, Cycles on the CPU,
# then checks it and redraws docs/sample_scene.png. About a minute on 2 cores.
# Usage: tools/scenes/make_scene.sh [output folder, default assets/tabletop] [extra make_scene.py options...]
# The renders are committed, so building and testing vknerf never needs Blender.
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT="${1:-assets/tabletop}"
shift || true
source tools/scenes/need_blender.sh
rm -rf "$OUT/train" "$OUT/test"
blender_module make_scene --out "$OUT" "$@"
# Debian's python3 (not a pyenv or venv one) has the packages installed above.
if [ "$OUT" = assets/tabletop ] && [ $# -eq 0 ]; then
  /usr/bin/python3 -m tools.scenes.check_scene "$OUT" --sheet docs/sample_scene.png
else
  /usr/bin/python3 -m tools.scenes.check_scene "$OUT"
fi
