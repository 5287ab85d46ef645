#!/usr/bin/env bash
# Renders the pictures of docs/mathematics.md: for one mesh of each topology, the checkerboard
# texture of its `ricci-flow --target auto` layout on the mesh, and the layout itself
# (docs/uniformization-*.png).
# Needs the Release build (scripts/build.sh release) and numpy (a venv under build/ is made).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bash "$here/scripts/setup.sh"
bash "$here/scripts/build.sh" release -DCMAKE_BUILD_TYPE=Release -DRICCI_BUILD_TESTS=OFF >/dev/null
tool="$here/build/release/cli/ricci-flow"
meshes="$here/third_party/cgal-data/data/meshes"
venv="$here/build/pictures-venv"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -c 'import numpy' 2>/dev/null || "$venv/bin/pip" install -q numpy
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# name mesh view-azimuth view-elevation checks [ricci-flow options] [-- renderer options]
while read -r name mesh azimuth elevation checks rest; do
  tool_options=${rest%%--render*}
  render_options=${rest#*--render}
  [ "$render_options" = "$rest" ] && render_options=""
  # shellcheck disable=SC2086
  "$tool" "$meshes/$mesh" -o "$work/$name.ply" --ascii $tool_options
  # shellcheck disable=SC2086
  "$venv/bin/python" "$here/scripts/render_pictures.py" "$work/$name.ply" \
    "$here/docs/uniformization-$name-mesh.png" "$here/docs/uniformization-$name-layout.png" \
    --view "$azimuth" "$elevation" --checks "$checks" $render_options
done <<'LIST'
disk nefertiti.off 180 0 16
sphere hand.off 0 0 24
torus knot1.off 0 0 72
genus2 eight.off 0 0 24 --no-flips --render --poincare
holes holes.off 0 0 16
LIST
echo "pictures: wrote $here/docs/uniformization-*.png"
