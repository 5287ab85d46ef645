#!/usr/bin/env bash
# The plugin in the real MeshLab GUI under Xvfb: MeshLab starts with the plugin, the filter is
# found under Filters > Texture, its dialog opens, and Apply colours the mesh by u.
# Usage (run by ctest under xvfb-run): meshlab_gui_test.sh PREFIX MESH ARTIFACT_DIR
set -euo pipefail
prefix=$1 mesh=$2 artifacts=$3
mkdir -p "$artifacts"
source "$(dirname "$0")/meshlab/gui_lib.sh"

# Fraction of pixels of the 3D view that the quality colour ramp makes green-dominant;
# MeshLab's grey mesh and blue background have none.
green_fraction() {
  view_of "$1" | convert - -fx "(g > r + 0.15 && g > b + 0.15) ? 1 : 0" -format "%[fx:mean]" info:
}

start_meshlab "$prefix" "$mesh"
import -window root "$artifacts/before.png"
xdotool key alt+l
sleep 1
xdotool key Up Up Right
sleep 1
import -window root "$artifacts/texture-menu.png"
xdotool key Escape Escape
sleep 1

# Ours is the 14th entry of the Texture submenu.
open_texture_filter 14 "Ricci Flow: Conformal Parameterization"
import -window root "$artifacts/dialog.png"
apply_and_close 4
no_failure_dialog "the filter's defaults"
import -window root "$artifacts/after.png"

before=$(green_fraction "$artifacts/before.png")
after=$(green_fraction "$artifacts/after.png")
echo "green-dominant pixels in the view: before $before, after $after"
awk -v b="$before" -v a="$after" 'BEGIN { exit !(b < 0.001 && a > 0.02) }' ||
  fail "applying the filter did not colour the mesh by u (before $before, after $after)"
echo "PASS: MeshLab GUI test; screenshots in $artifacts"
