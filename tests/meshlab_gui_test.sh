#!/usr/bin/env bash
# The plugin in the real MeshLab GUI under Xvfb: MeshLab starts with the plugin, the filter is
# found under Filters > Texture, its dialog opens, and Apply colours the mesh by u.
# Usage (run by ctest under xvfb-run): meshlab_gui_test.sh PREFIX MESH ARTIFACT_DIR
set -euo pipefail
prefix=$1 mesh=$2 artifacts=$3
filter="Ricci Flow: Conformal Parameterization"
mkdir -p "$artifacts"
log="$artifacts/meshlab-gui.log"

"$prefix/bin/meshlab" "$mesh" >"$log" 2>&1 &
pid=$!
trap 'kill $pid 2>/dev/null || true' EXIT

fail() {
  import -window root "$artifacts/failure.png" 2>/dev/null || true
  echo "FAIL: $*" >&2
  exit 1
}

# Waits up to $2 seconds for a visible window whose name matches $1; prints its id.
wait_window() {
  local id=""
  for _ in $(seq $((10 * $2))); do
    id=$(xdotool search --onlyvisible --name "$1" 2>/dev/null | head -1 || true)
    [ -n "$id" ] && { echo "$id"; return 0; }
    sleep 0.1
  done
  return 1
}

# Fraction of pixels of the 3D view that the quality colour ramp makes green-dominant;
# MeshLab's grey mesh and blue background have none.
green_fraction() {
  convert "$1" -crop 840x760+10+80 +repage -fx "(g > r + 0.15 && g > b + 0.15) ? 1 : 0" \
    -format "%[fx:mean]" info:
}

main=$(wait_window "^MeshLab" 60) || fail "MeshLab's window did not appear"
xdotool windowsize "$main" 1280 1000
xdotool windowfocus --sync "$main"
sleep 2
import -window root "$artifacts/before.png"

# Filters (Alt+L) > Texture (second from the bottom) > the filter. In Debian's MeshLab 2020.09
# the Texture submenu lists its filters alphabetically; ours is the 14th.
xdotool key alt+l
sleep 1
xdotool key Up Up Right
sleep 1
import -window root "$artifacts/texture-menu.png"
for _ in $(seq 13); do xdotool key Down; done
xdotool key Return
dialog=$(wait_window "^$filter\$" 20) || fail "the dialog of '$filter' did not open from Filters > Texture"
sleep 1
import -window root "$artifacts/dialog.png"

# Apply (the dialog's bottom-right button), then Close (bottom-left) to uncover the view.
eval "$(xdotool getwindowgeometry --shell "$dialog")"
xdotool mousemove --window "$dialog" $((WIDTH * 3 / 4)) $((HEIGHT - 22)) click 1
sleep 4
import -window root "$artifacts/applied.png"
xdotool mousemove --window "$dialog" $((WIDTH / 4)) $((HEIGHT - 22)) click 1
sleep 2
import -window root "$artifacts/after.png"

before=$(green_fraction "$artifacts/before.png")
after=$(green_fraction "$artifacts/after.png")
echo "green-dominant pixels in the view: before $before, after $after"
awk -v b="$before" -v a="$after" 'BEGIN { exit !(b < 0.001 && a > 0.02) }' ||
  fail "applying the filter did not colour the mesh by u (before $before, after $after)"
echo "PASS: MeshLab GUI test; screenshots in $artifacts"
