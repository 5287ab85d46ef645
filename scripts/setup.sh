#!/usr/bin/env bash
# One-command setup for a Debian 12 machine (run as root, or with sudo available).
# Installs the Debian packages the project needs and fetches, into ignored folders,
# MeshLab's source package (headers and vcglib), the CGAL CC0 mesh data set, and a root of Debian
# unstable with its MeshLab 2025.07.
# Idempotent: when everything is present it returns in about a second.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
third_party="$here/third_party"
meshlab_version="2020.09+dfsg1-2"
# MeshLab 2025.07 (the one pymeshlab 2025.7 bundles): only the upstream tarball of Debian's
# unstable source package is used, fetched with a private apt state so the system stays bookworm.
meshlab2025_version="2025.07~dfsg-4"
meshlab2025_tarball="meshlab_2025.07~dfsg.orig.tar.xz"
pymeshlab_version="2025.7.post1"
pytest_version="8.3.4"
cgal_demo_package="libcgal-demo"

packages=(
  build-essential cmake pkg-config dpkg-dev ccache clang-format clang-14 libclang-rt-14-dev llvm-14
  libeigen3-dev libsuitesparse-dev libopenblas0-pthread zlib1g-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  qtbase5-dev libqt5opengl5-dev libglew-dev
  "meshlab=$meshlab_version"
  xvfb xauth xdotool imagemagick debootstrap
  python3-venv python3-dev xz-utils
)

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi
}

missing_packages() {
  local p name
  for p in "${packages[@]}"; do
    name=${p%%=*}
    dpkg-query -W -f='${Status}' "$name" 2>/dev/null | grep -q "install ok installed" || echo "$p"
  done
}

# --- Debian packages
missing=$(missing_packages)
if [ -n "$missing" ]; then
  echo "setup: installing Debian packages: $(echo $missing)"
  as_root apt-get update -qq
  # shellcheck disable=SC2086
  DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -qq --no-install-recommends $missing
fi

# --- deb-src lines, derived from the machine's own sources file (no address is written here)
ensure_deb_src() {
  local own=/etc/apt/sources.list.d/debian.sources
  local src=/etc/apt/sources.list.d/ricci-flow-deb-src.sources
  if [ -f "$src" ] || grep -qs '^Types:.*deb-src' "$own"; then return; fi
  if [ ! -f "$own" ]; then
    echo "setup: $own not found; add deb-src lines for bookworm by hand and rerun" >&2
    exit 1
  fi
  sed -e 's/^Types:.*/Types: deb-src/' "$own" | as_root tee "$src" >/dev/null
  as_root apt-get update -qq
}

# --- MeshLab's source package, exactly the installed version (headers and vcglib)
meshlab_src="$third_party/meshlab"
if [ ! -f "$meshlab_src/.complete" ]; then
  ensure_deb_src
  rm -rf "$meshlab_src" && mkdir -p "$meshlab_src"
  echo "setup: fetching meshlab=$meshlab_version source into $meshlab_src"
  (cd "$meshlab_src" && apt-get source -qq "meshlab=$meshlab_version" >/dev/null)
  dir=$(find "$meshlab_src" -maxdepth 1 -mindepth 1 -type d -name 'meshlab-*' | head -1)
  [ -d "$dir/vcglib" ] || { echo "setup: $dir has no vcglib/" >&2; exit 1; }
  ln -sfn "$(basename "$dir")" "$meshlab_src/source"
  touch "$meshlab_src/.complete"
fi

# --- CGAL's CC0 mesh data set (real meshes of every topology), for tests and benchmarks
cgal_data="$third_party/cgal-data"
if [ ! -f "$cgal_data/.complete" ]; then
  rm -rf "$cgal_data" && mkdir -p "$cgal_data"
  echo "setup: fetching $cgal_demo_package's mesh data set into $cgal_data"
  (cd "$cgal_data" && apt-get download -qq "$cgal_demo_package" >/dev/null)
  deb=$(ls "$cgal_data"/${cgal_demo_package}_*.deb | head -1)
  dpkg-deb -x "$deb" "$cgal_data/pkg"
  tarball=$(find "$cgal_data/pkg" -name 'data.tar.gz' | head -1)
  if [ -z "$tarball" ]; then
    echo "setup: $deb has no data.tar.gz" >&2
    exit 1
  fi
  tar -xzf "$tarball" -C "$cgal_data" data/meshes
  rm -rf "$cgal_data/pkg" "$deb"
  touch "$cgal_data/.complete"
fi

# --- MeshLab 2025.07's source (headers and vcglib for the plugin pymeshlab loads)
meshlab2025_src="$third_party/meshlab-2025.07"
if [ ! -f "$meshlab2025_src/.complete" ]; then
  rm -rf "$meshlab2025_src" && mkdir -p "$meshlab2025_src/apt/lists/partial" \
    "$meshlab2025_src/apt/cache/archives/partial" "$meshlab2025_src/apt/sources.list.d"
  : >"$meshlab2025_src/apt/sources.list"
  own=/etc/apt/sources.list.d/debian.sources
  if [ ! -f "$own" ]; then
    echo "setup: $own not found; cannot derive a deb-src entry for MeshLab 2025.07" >&2
    exit 1
  fi
  # The machine's first entry, as deb-src of the unstable suite (no address is written here).
  sed -n '1,/^$/p' "$own" | sed -e '/^#/d' -e 's/^Types:.*/Types: deb-src/' \
    -e 's/^Suites:.*/Suites: unstable/' >"$meshlab2025_src/apt/sources.list.d/unstable-src.sources"
  private_apt=(-o "Dir::State::Lists=$meshlab2025_src/apt/lists"
    -o "Dir::Etc::sourcelist=$meshlab2025_src/apt/sources.list"
    -o "Dir::Etc::sourceparts=$meshlab2025_src/apt/sources.list.d"
    -o "Dir::Cache=$meshlab2025_src/apt/cache")
  echo "setup: fetching MeshLab $meshlab2025_version's upstream source into $meshlab2025_src"
  apt-get "${private_apt[@]}" update -qq
  # The upstream tarball is all we need; the package's .dsc may be gone from the mirror, which
  # makes apt-get exit non-zero after the tarball arrived, so the tarball itself is checked.
  (cd "$meshlab2025_src" &&
    apt-get "${private_apt[@]}" source --download-only -qq "meshlab=$meshlab2025_version" \
      >/dev/null 2>&1 || true)
  if [ ! -f "$meshlab2025_src/$meshlab2025_tarball" ]; then
    echo "setup: apt-get source meshlab=$meshlab2025_version did not fetch $meshlab2025_tarball" >&2
    exit 1
  fi
  tar -xf "$meshlab2025_src/$meshlab2025_tarball" -C "$meshlab2025_src"
  dir=$(find "$meshlab2025_src" -maxdepth 1 -mindepth 1 -type d -name 'meshlab-*' | head -1)
  [ -f "$dir/src/common/plugins/interfaces/filter_plugin.h" ] ||
    { echo "setup: $dir has no src/common/plugins/interfaces/filter_plugin.h" >&2; exit 1; }
  ln -sfn "$(basename "$dir")" "$meshlab2025_src/source"
  rm -rf "$meshlab2025_src/apt" "$meshlab2025_src"/*.tar.* "$meshlab2025_src"/*.dsc
  touch "$meshlab2025_src/.complete"
fi

# --- MeshLab 2025.07's GUI: Debian unstable's meshlab in a root of its own, with what the plugin
# is built with there (scripts/meshlab2025_root.sh; about 2 minutes and 1.3 GiB)
bash "$here/scripts/meshlab2025_root.sh" ensure "$third_party/meshlab-2025.07-root"

# --- a Python with pymeshlab (its wheel carries MeshLab 2025.07) and pytest
venv="$third_party/pymeshlab-venv"
if [ ! -f "$venv/.complete-$pymeshlab_version" ]; then
  rm -rf "$venv"
  echo "setup: installing pymeshlab==$pymeshlab_version and pytest into $venv"
  python3 -m venv "$venv"
  "$venv/bin/pip" install -q "pymeshlab==$pymeshlab_version" "pytest==$pytest_version"
  touch "$venv/.complete-$pymeshlab_version"
fi

# --- real meshes as users bring them (meshes/real-meshes.tsv: their packages and licences)
bash "$here/scripts/real_meshes.sh"
