#!/usr/bin/env bash
# MeshLab 2025.07's GUI from Debian's own packages: a root of Debian unstable (debootstrap) with
# its `meshlab` and what the plugin is built with there, kept in the ignored third_party/.
#
#   meshlab2025_root.sh create ROOT      debootstrap ROOT, install meshlab and the build packages,
#                                        stamp ROOT/.complete
#   meshlab2025_root.sh ensure ROOT      create ROOT unless its stamp is current (scripts/setup.sh)
#   meshlab2025_root.sh run ROOT CMD...  CMD inside ROOT, in a private mount namespace with /proc,
#                                        /dev, /sys, /tmp (the X server's socket and cookie) and the
#                                        checkout (at its own path) mounted; the mounts end with CMD
#
# The mirror is the machine's own: the first URI of its /etc/apt/sources.list.d/debian.sources,
# read at run time (no address is written here). Run as root (or with sudo).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
suite=unstable
meshlab_line=2025.07 # the MeshLab version the root must carry (its plugin check: 6 characters)

# What the plugin is built and tested with inside the root: Debian unstable's meshlab and the
# Qt 5 it is built against, the project's own dependencies, Mesa's software OpenGL for Xvfb, a
# font for the dialogs.
# meshlab comes with its recommends: the libraries some of its own plugins need (muparser, qhull,
# lib3ds, OpenCTM); without them MeshLab opens with an error listing those plugins.
root_packages=(
  libgl1-mesa-dri fonts-dejavu-core
  g++ make cmake pkg-config qtbase5-dev libqt5opengl5-dev libglew-dev
  libeigen3-dev libsuitesparse-dev zlib1g-dev ccache
)

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi
}

# The first URI of the machine's first deb entry.
own_mirror() {
  local own=/etc/apt/sources.list.d/debian.sources uri
  if [ ! -f "$own" ]; then
    echo "meshlab2025_root: $own not found; cannot derive a mirror for debootstrap" >&2
    exit 1
  fi
  uri=$(sed -n '1,/^$/p' "$own" | awk '/^URIs:/ { print $2; exit }')
  if [ -z "$uri" ]; then
    echo "meshlab2025_root: no URIs: line in the first entry of $own" >&2
    exit 1
  fi
  echo "$uri"
}

# The command that runs CMD... as root inside ROOT: the mounts are private to CMD's mount
# namespace, so they vanish when it ends, whatever way it ends, and runs side by side do not
# meet. Every step execs the next, so CMD keeps the process id (a test can stop MeshLab by it).
in_root=(unshare --mount --propagation private -- bash -c '
  set -euo pipefail
  root=$1 checkout=$2
  shift 2
  mount -t proc proc "$root/proc"
  mount --rbind /dev "$root/dev"
  mount --rbind /sys "$root/sys"
  mount --bind /tmp "$root/tmp"
  mkdir -p "$root$checkout"
  mount --bind "$checkout" "$root$checkout"
  exec chroot "$root" /usr/bin/env -i HOME=/root PATH=/usr/sbin:/usr/bin:/sbin:/bin \
    LANG=C.UTF-8 ${DISPLAY:+DISPLAY=$DISPLAY} ${XAUTHORITY:+XAUTHORITY=$XAUTHORITY} "$@"
' bash)
if [ "$(id -u)" -ne 0 ]; then in_root=(sudo "${in_root[@]}"); fi

run_in_root() {
  local root=$1
  shift
  "${in_root[@]}" "$root" "$here" "$@"
}

# What .complete holds: the suite and the packages asked for (a change makes a new root).
stamp() {
  echo "$suite meshlab ${root_packages[*]}"
}

create_root() {
  local root=$1 mirror start
  start=$(date +%s)
  mirror=$(own_mirror)
  # A mount inside the root (the checkout bound there by a run left behind) would let rm reach
  # beyond it.
  if awk -v r="$root/" 'index($5, r) == 1 { found = 1 } END { exit !found }' /proc/self/mountinfo
  then
    echo "meshlab2025_root: something is mounted inside $root; unmount it first" >&2
    exit 1
  fi
  as_root rm -rf "$root"
  mkdir -p "$(dirname "$root")"
  echo "meshlab2025_root: debootstrap of Debian $suite into $root (the machine's own mirror)"
  # In a mount namespace of its own: an interrupted debootstrap leaves no mounts behind.
  as_root unshare --mount --propagation private -- \
    debootstrap --variant=minbase --keyring=/usr/share/keyrings/debian-archive-keyring.gpg \
    "$suite" "$root" "$mirror" >"$root.log" 2>&1 ||
    { tail -n 30 "$root.log"; echo "meshlab2025_root: debootstrap failed ($root.log)" >&2; exit 1; }
  # The machine's mirror may serve a frozen copy of unstable (as this project's CI machine does)
  # whose Release file is past its Valid-Until date; its signature is still checked.
  echo 'Acquire::Check-Valid-Until "false";' |
    as_root tee "$root/etc/apt/apt.conf.d/50ricci-frozen-mirror" >/dev/null
  echo "meshlab2025_root: installing meshlab, ${root_packages[*]} in the root"
  run_in_root "$root" apt-get update -qq >>"$root.log" 2>&1 ||
    { tail -n 30 "$root.log"; exit 1; }
  run_in_root "$root" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
    --no-install-recommends "${root_packages[@]}" >>"$root.log" 2>&1 ||
    { tail -n 30 "$root.log"; exit 1; }
  run_in_root "$root" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq meshlab \
    >>"$root.log" 2>&1 || { tail -n 30 "$root.log"; exit 1; }
  run_in_root "$root" apt-get clean
  local version
  version=$(run_in_root "$root" dpkg-query -W -f='${Version}' meshlab)
  case "$version" in
  "$meshlab_line"*) ;;
  *)
    echo "meshlab2025_root: Debian $suite's meshlab is $version, not $meshlab_line" >&2
    exit 1
    ;;
  esac
  [ -f "$root/usr/lib/x86_64-linux-gnu/meshlab/libmeshlab-common.so" ] ||
    { echo "meshlab2025_root: no libmeshlab-common.so in the root's meshlab" >&2; exit 1; }
  echo "$version" | as_root tee "$root/.meshlab-version" >/dev/null
  rm -f "$root.log"
  stamp | as_root tee "$root/.complete" >/dev/null
  echo "meshlab2025_root: meshlab $version in $root in $(($(date +%s) - start)) s," \
    "$(du -sh "$root" | cut -f1)"
}

[ $# -ge 2 ] || set -- usage
root=$(realpath -m "${2:-.}")
case "$1" in
create) create_root "$root" ;;
ensure)
  if [ "$(cat "$root/.complete" 2>/dev/null)" != "$(stamp)" ]; then create_root "$root"; fi
  ;;
run)
  shift 2
  [ -f "$root/.complete" ] || { echo "meshlab2025_root: $root is not set up" >&2; exit 1; }
  exec "${in_root[@]}" "$root" "$here" "$@"
  ;;
*)
  echo "usage: $0 create ROOT | ensure ROOT | run ROOT CMD..." >&2
  exit 2
  ;;
esac
