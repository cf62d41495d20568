#!/usr/bin/env bash
# Installs vknerf's build and test dependencies from Debian 12 packages (root or sudo).
# clang and libclang-rt-dev (libFuzzer, the sanitizer runtimes): tools/sanitize.sh.
# ffmpeg: `vknerf render --video` runs it (and its tests); `vknerf process` too, for a video.
# colmap: `vknerf process` runs it (and its end-to-end test).
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update
$SUDO apt-get install -y --no-install-recommends \
  build-essential cmake pkg-config git \
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools glslang-tools \
  libglm-dev libstb-dev libturbojpeg0-dev nlohmann-json3-dev libcli11-dev \
  libgtest-dev googletest libbenchmark-dev libopenblas-dev \
  libglfw3-dev xvfb xauth python3-matplotlib python3-numpy \
  clang libclang-rt-dev ffmpeg colmap
