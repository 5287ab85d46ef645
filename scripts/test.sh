#!/usr/bin/env bash
# Set up, check formatting, build with warnings as errors, and run every test: once in a Release
# build, once more in a build with the address and undefined-behaviour sanitizers, the fuzz
# targets on their regression inputs and for half a minute each, the plugin built for MeshLab 2025.07
# loaded into pymeshlab (pytest), the plugin built for Debian unstable's MeshLab 2025.07 in its GUI
# (Xvfb), and the Python wheel installed into a fresh venv (pytest).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# Each stage's line says when it began and how long after the command's start (pytest's summary
# stays the last line).
started=$(date +%s)
stage() { echo "== $(date +%T), $((($(date +%s) - started) / 60)) min in: $*"; }
bash "$root/scripts/setup.sh"

stage "formatting (.clang-format)"
(cd "$root" && git ls-files '*.cpp' '*.h' | xargs clang-format --dry-run --Werror)

stage "release build and tests"
bash "$root/scripts/build.sh" test -DCMAKE_BUILD_TYPE=Release -DRICCI_WARNINGS_AS_ERRORS=ON \
  -DRICCI_BUILD_PLUGIN=ON
ctest --test-dir "$root/build/test" --output-on-failure --parallel "$(nproc)"

stage "sanitizer build (address, undefined) and tests"
bash "$root/scripts/build.sh" asan -DCMAKE_BUILD_TYPE=Debug -DRICCI_SANITIZE=ON \
  -DRICCI_WARNINGS_AS_ERRORS=ON -DRICCI_BUILD_PLUGIN=ON
ASAN_OPTIONS=detect_leaks=1 ctest --test-dir "$root/build/asan" --output-on-failure \
  --parallel "$(nproc)"

stage "fuzz targets (libFuzzer, ASan and UBSan): regression inputs, then 30 s each"
bash "$root/scripts/fuzz.sh" 30

stage "plugin for MeshLab 2025.07, loaded by pymeshlab (pytest)"
bash "$root/scripts/build.sh" pymeshlab -DCMAKE_BUILD_TYPE=Release -DRICCI_WARNINGS_AS_ERRORS=ON \
  -DRICCI_BUILD_PLUGIN=ON -DRICCI_BUILD_CLI=OFF \
  -DRICCI_MESHLAB_SOURCE="$root/third_party/meshlab-2025.07/source" \
  -DRICCI_PYMESHLAB_PYTHON="$root/third_party/pymeshlab-venv/bin/python"
ctest --test-dir "$root/build/pymeshlab" --output-on-failure --verbose -R Pymeshlab

stage "plugin for MeshLab 2025.07 in its GUI: built in Debian unstable's root, tested under Xvfb"
# Built inside the root (its g++, Qt and MeshLab 2025.07, Debian's float build), without -Werror:
# that compiler and Eigen are newer than the ones the warnings are kept clean for above.
root25="$root/third_party/meshlab-2025.07-root"
in_root25() { bash "$root/scripts/meshlab2025_root.sh" run "$root25" "$@"; }
in_root25 cmake -S "$root" -B "$root/build/meshlab2025" -DCMAKE_BUILD_TYPE=Release \
  -DRICCI_BUILD_PLUGIN=ON -DRICCI_BUILD_CLI=OFF -DRICCI_BUILD_TESTS=ON \
  -DRICCI_PLUGIN_FOR=meshlab -DRICCI_MESHLAB_SOURCE="$root/third_party/meshlab-2025.07/source" \
  -DCMAKE_CXX_COMPILER_LAUNCHER=ccache >"$root/build-meshlab2025.log" 2>&1 &&
  in_root25 cmake --build "$root/build/meshlab2025" --target filter_ricci_flow \
    --parallel "$(nproc)" >>"$root/build-meshlab2025.log" 2>&1 ||
  { tail -n 60 "$root/build-meshlab2025.log"; exit 1; }
rm -f "$root/build-meshlab2025.log"
ctest --test-dir "$root/build/meshlab2025" --output-on-failure --no-tests=error -R Meshlab2025Gui

stage "Python wheel: built into dist/, installed into a fresh venv, tested there (pytest)"
bash "$root/scripts/wheel.sh"
(cd "$root/build" && "$root/build/wheel-venv/bin/python" -m pytest -q -p no:cacheprovider \
  "$root/python/tests")
