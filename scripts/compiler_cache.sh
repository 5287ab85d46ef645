# Sourced by build.sh and wheel.sh: where ccache is installed (setup.sh installs it), every build
# compiles through it, with paths taken relative to the checkout, so that a file unchanged since
# an earlier build, of any folder or clone, is not compiled again.
if command -v ccache >/dev/null 2>&1; then
  export CMAKE_C_COMPILER_LAUNCHER=ccache CMAKE_CXX_COMPILER_LAUNCHER=ccache
  export CCACHE_BASEDIR="$root" CCACHE_NOHASHDIR=1
fi
