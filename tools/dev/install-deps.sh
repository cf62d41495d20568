#!/usr/bin/env bash
# Installs vknerf's dependencies from Debian 12 packages (root or sudo).
#   (no argument)  what the main job needs (the README's first command): build the vknerf command
#                  line and run it on lavapipe.
#   --all          that, and what the rest needs (the README's second command, .ci/run): the test
#                  suite (GoogleTest, the validation layer, vulkaninfo), OpenBLAS for `bench mlp`,
#                  tools/dev/sanitize.sh (clang, libclang-rt-dev: the sanitizer runtimes and
#                  libFuzzer), the viewer and its test (GLFW, Xvfb), the
#                  plotting scripts (matplotlib, numpy), the Python module and its tests (pybind11,
#                  python3-dev, numpy, pytest), and the programs `vknerf process` runs
#                  (colmap; ffmpeg for a video) and `render --video` runs (ffmpeg), which their tests
#                  run too.
set -euo pipefail
ALL=0
case "${1:-}" in
  "") ;;
  --all) ALL=1 ;;
  *) echo "usage: $0 [--all]" >&2; exit 2 ;;
esac
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi
export DEBIAN_FRONTEND=noninteractive
MAIN="build-essential cmake pkg-config \
  libvulkan-dev mesa-vulkan-drivers glslang-tools \
  libglm-dev libstb-dev libturbojpeg0-dev nlohmann-json3-dev libcli11-dev"
REST="git vulkan-validationlayers vulkan-tools \
  libgtest-dev googletest libopenblas-dev \
  libglfw3-dev xvfb xauth python3-matplotlib python3-numpy \
  pybind11-dev python3-pybind11 python3-dev python3-pytest \
  clang libclang-rt-dev ffmpeg colmap"
PACKAGES=$MAIN
if [ "$ALL" = 1 ]; then PACKAGES="$MAIN $REST"; fi
$SUDO apt-get update
# shellcheck disable=SC2086  # one word per package
$SUDO apt-get install -y --no-install-recommends $PACKAGES
