# Sourced by tools/scenes/make_*.sh (from the repository root): installs Debian's blender, python3-numpy and
# python3-pil where missing, and defines blender_module.
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

# blender_module NAME ARGS...: runs tools/scenes/<NAME>.py inside Blender, headless, as python3 -m would (a
# module of the tools.scenes package, so its relative imports work), with ARGS after "--" for the module.
# --factory-startup: ignore any user preferences or startup file, so every machine renders the same scene;
# --python-use-system-env: Blender's Python honours PYTHONPATH, which names the repository root.
blender_module() {
  local module=$1
  shift
  PYTHONPATH="$PWD${PYTHONPATH:+:$PYTHONPATH}" blender -b --factory-startup --python-use-system-env \
    --python-expr "import runpy; runpy.run_module('tools.scenes.$module', run_name='__main__')" -- "$@"
}
