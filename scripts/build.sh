#!/usr/bin/env bash
# Configure and build into build/NAME. Usage: build.sh NAME [cmake options...]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
name=$1
shift
source "$root/scripts/compiler_cache.sh"
cmake -S "$root" -B "$root/build/$name" "$@" >"$root/build-$name.log" 2>&1 ||
  { cat "$root/build-$name.log"; exit 1; }
cmake --build "$root/build/$name" --parallel "$(nproc)" >>"$root/build-$name.log" 2>&1 ||
  { tail -n 60 "$root/build-$name.log"; exit 1; }
rm -f "$root/build-$name.log"
