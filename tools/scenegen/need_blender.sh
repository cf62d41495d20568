# Sourced by tools/make_*.sh: installs Debian's blender, python3-numpy and python3-pil where missing.
need=()
command -v blender >/dev/null 2>&1 || need+=(blender)
/usr/bin/python3 -c "import numpy, PIL" 2>/dev/null || need+=(python3-numpy python3-pil)
if [ ${#need[@]} -gt 0 ]; then
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update
  $SUDO apt-get install -y --no-install-recommends "${need[@]}"
fi
