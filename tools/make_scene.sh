#!/usr/bin/env bash
# Regenerates the shipped sample scene (assets/tabletop) with Debian's Blender, headless, Cycles on the CPU.
# Usage: tools/make_scene.sh [output folder, default assets/tabletop] [extra make_scene.py options...]
# Takes a few minutes on 2 cores. The renders are committed, so tests never need Blender.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT="${1:-assets/tabletop}"
shift || true
if ! command -v blender >/dev/null 2>&1; then
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update
  $SUDO apt-get install -y --no-install-recommends blender
fi
rm -rf "$OUT/train" "$OUT/test"
# --factory-startup: ignore any user preferences or startup file, so every machine renders the same scene.
blender -b --factory-startup -P tools/make_scene.py -- --out "$OUT" "$@"
