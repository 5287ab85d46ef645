#!/usr/bin/env bash
# The plugin in MeshLab 2025.07's own GUI, Debian unstable's meshlab in the root scripts/setup.sh
# makes (scripts/meshlab2025_root.sh), under Xvfb, driven as a user drives it:
#   1. the plugin installed into that MeshLab's plugins folder (cmake --install), MeshLab starts
#      without refusing it (its loader checks the version and the scalar type);
#   2. a face scan, Filters > Texture > the filter with its defaults, Apply: the log's summary,
#      no failure dialog, and the mesh, exported by MeshLab as OBJ, has a texture coordinate per
#      vertex in [0, 1]^2;
#   3. the cow, the target set to the texture atlas in the dialog, Apply, then MeshLab's Set
#      Texture with its dummy checkerboard: the log's atlas line, the checkerboard on the mesh,
#      and the exported OBJ's faces all carry texture coordinates in [0, 1]^2;
#   4. a Moebius strip (not orientable): MeshLab's failure dialog with the filter's reason, and
#      the exported mesh is the input, without texture coordinates.
# Usage (run by ctest under xvfb-run): meshlab2025_gui_test.sh ROOT BUILD_DIR ARTIFACT_DIR
set -euo pipefail
root=$(realpath -m "$1") build=$(realpath -m "$2") artifacts=$(realpath -m "$3")
here=$(cd "$(dirname "$0")" && pwd)
checkout=$(cd "$here/.." && pwd)
rm -rf "$artifacts"
mkdir -p "$artifacts"
source "$here/meshlab/gui_lib.sh"
in_root() { bash "$checkout/scripts/meshlab2025_root.sh" run "$root" "$@"; }

# --- 1. the plugin where Debian's MeshLab loads plugins, as a user installs it
plugin_dir=/usr/lib/x86_64-linux-gnu/meshlab/plugins
in_root cmake --install "$build" --component meshlab_plugin >"$artifacts/install.log" 2>&1 ||
  { cat "$artifacts/install.log"; fail "cmake --install of the plugin failed in the root"; }
# (cmake --install rewrites the run path, so the files are compared by their build ids.)
build_id() { readelf -n "$1" | awk '/Build ID/ { print $3 }'; }
[ -n "$(build_id "$build/plugin/libfilter_ricci_flow.so")" ] &&
  [ "$(build_id "$build/plugin/libfilter_ricci_flow.so")" = \
    "$(build_id "$root$plugin_dir/libfilter_ricci_flow.so")" ] ||
  fail "the plugin in $root$plugin_dir is not the one just built"
echo "MeshLab $(cat "$root/.meshlab-version") in $root; the plugin installed into $plugin_dir"

# Every line MeshLab logs also goes to qDebug ("LOG: level text"), which Debian's Qt silences
# unless asked: the log file is how the test reads MeshLab's log panel.
log="$artifacts/meshlab-gui.log"

# The id of a visible window whose name matches $1, or nothing.
visible() {
  xdotool search --onlyvisible --name "$1" 2>/dev/null | head -1 || true
}

# Waits up to $2 seconds for a line of MeshLab's log matching the extended regex $1.
wait_log() {
  for _ in $(seq $((10 * $2))); do
    grep -Eq "$1" "$log" && return 0
    sleep 0.1
  done
  return 1
}

# meshlab_on MESH: MeshLab 2025.07 on MESH (a path inside the checkout, which the root sees at the
# same path), its window 1280x1000 and focused; sets `main`. A fresh home: no settings carried
# over between runs.
meshlab_on() {
  [ -z "${meshlab_pid:-}" ] || { kill "$meshlab_pid" 2>/dev/null || true; wait "$meshlab_pid" || true; }
  rm -rf "$artifacts/home" && mkdir -p "$artifacts/home"
  : >"$log"
  # The X server answers before MeshLab starts (xvfb-run's server is started with -noreset, so
  # the last client leaving does not reset it; this is the check that it is there).
  for _ in $(seq 100); do xdotool getdisplaygeometry >/dev/null 2>&1 && break; sleep 0.1; done
  xdotool getdisplaygeometry >/dev/null 2>&1 || fail "the X server on $DISPLAY does not answer"
  bash "$checkout/scripts/meshlab2025_root.sh" run "$root" env HOME="$artifacts/home" \
    QT_LOGGING_RULES="default.debug=true" meshlab "$1" >"$log" 2>&1 &
  meshlab_pid=$!
  trap 'kill $meshlab_pid 2>/dev/null || true' EXIT
  # MeshLab reports plugins it refuses (another version, another scalar) in a message box
  # before its main window shows.
  local id=""
  for _ in $(seq 600); do
    if [ -n "$(visible "^Error while loading plugins")" ]; then
      fail "MeshLab refused a plugin (the screenshot failure.png says which and why)"
    fi
    id=$(visible "^MeshLab 2025")
    [ -n "$id" ] && break
    kill -0 "$meshlab_pid" 2>/dev/null || { cat "$log"; fail "MeshLab exited on start"; }
    sleep 0.2
  done
  [ -n "$id" ] || fail "MeshLab 2025.07's window did not appear in 120 s"
  main=$id
  wait_log "All files opened" 60 || fail "MeshLab did not open $1"
  xdotool windowsize "$main" 1280 1000
  xdotool windowfocus --sync "$main"
  sleep 1
}

# Filters (Alt+L) > Texture (third from the bottom in 2025.07) with its submenu open; $1 seconds
# for each menu to open.
texture_menu() {
  xdotool windowfocus --sync "$main"
  xdotool key alt+l
  sleep "${1:-0.5}"
  xdotool key Up Up Up Right
  sleep "${1:-0.5}"
}

# filter_dialog N NAME: the N-th entry of Filters > Texture, whose dialog is titled NAME, moved
# to the screen's top (it is taller than the main window); sets `dialog`. A menu that opened too
# late for its keys (a busy machine) is closed and tried again, slower.
filter_dialog() {
  local attempt
  for attempt in 1 2 3; do
    texture_menu "$attempt"
    for _ in $(seq $(($1 - 1))); do xdotool key Down; done
    xdotool key Return
    if dialog=$(wait_window "^$2\$" 20); then
      xdotool windowmove "$dialog" 300 0
      xdotool windowfocus --sync "$dialog"
      sleep 0.5
      return 0
    fi
    echo "the dialog of '$2' did not open (attempt $attempt); the menus closed, again" >&2
    xdotool key Escape Escape Escape
    sleep 1
  done
  fail "the dialog of '$2' did not open from Filters > Texture"
}

# click_dialog FRACTION: a click on the dialog's bottom row (Close at 1/4, Apply at 3/4).
click_dialog() {
  eval "$(xdotool getwindowgeometry --shell "$dialog")"
  xdotool mousemove --window "$dialog" $((WIDTH * $1 / 4)) $((HEIGHT - 22)) click 1
}

# close_dialog: Close, then waits until the dialog is gone (and a second for the view to repaint)
# before anything is screenshot.
close_dialog() {
  local id
  id=$dialog
  click_dialog 1
  for _ in $(seq 100); do
    xdotool search --onlyvisible --name "." 2>/dev/null | grep -qx "$id" ||
      { sleep 1; return 0; }
    sleep 0.2
  done
  fail "a filter's dialog did not close within 20 s"
}

# apply FILTER_NAME SECONDS: Apply, then waits for the log to say the filter was applied (returns
# 0) or for MeshLab's failure dialog (returns 1; MeshLab logs the failure once it is closed).
apply() {
  local before
  before=$(wc -l <"$log")
  click_dialog 3
  for _ in $(seq $((5 * $2))); do
    if tail -n +"$((before + 1))" "$log" | grep -q "^LOG: .*Applied filter: $1 in"; then return 0; fi
    [ -z "$(visible "^Filter Failure$")" ] || return 1
    sleep 0.2
  done
  fail "$1: neither applied nor failed within $2 s"
}

# export_obj FILE: File > Export Mesh As (Ctrl+Shift+E), FILE typed, MeshLab's saving options
# accepted as they are offered.
export_obj() {
  xdotool windowfocus --sync "$main"
  xdotool key ctrl+shift+e
  local id
  id=$(wait_window '^Save ".*" Layer$' 30) || fail "File > Export Mesh As did not open"
  xdotool windowfocus --sync "$id"
  xdotool key ctrl+a
  xdotool type --delay 20 "$1"
  xdotool key Return
  id=$(wait_window "^Choose Saving Options" 30) || fail "no saving options for $1"
  xdotool windowfocus --sync "$id"
  xdotool key Return
  wait_log "Saved Mesh $1" 60 || fail "MeshLab did not save $1"
}

# obj_uv FILE: "vertices faces texcoords faces_with_texcoords texcoords_in_unit_square".
obj_uv() {
  awk '/^v /{v++} /^vt /{t++; if ($2 >= 0 && $2 <= 1 && $3 >= 0 && $3 <= 1) u++}
       /^f /{f++; if (split($2, a, "/") >= 2 && a[2] != "") ft++}
       END {print v + 0, f + 0, t + 0, ft + 0, u + 0}' "$1"
}

# --- 2. the defaults on a face scan (a disk): the unit disk, a texture coordinate per vertex
cp "$checkout/meshes/nefertiti.off" "$artifacts/"
meshlab_on "$artifacts/nefertiti.off"
import -window root "$artifacts/before.png"
texture_menu
import -window root "$artifacts/texture-menu.png"
xdotool key Escape Escape
sleep 0.5
filter_dialog 14 "Ricci Flow: Conformal Parameterization"
import -window "$dialog" "$artifacts/dialog.png"
apply "Ricci Flow: Conformal Parameterization" 120 || fail "the filter failed with its defaults"
no_failure_dialog "the filter's defaults"
grep -q "^LOG: 2 Ricci flow on nefertiti.off: disk, 299 vertices, 562 faces" "$log" ||
  fail "the log has no summary of the run"
grep -Eq "^LOG: 2 Layout \(plane\): 0 of the input's faces flipped" "$log" ||
  fail "the log's layout line is missing or reports flipped faces"
close_dialog
import -window root "$artifacts/after.png"
export_obj "$artifacts/nefertiti-uv.obj"
read -r v f t ft u <<<"$(obj_uv "$artifacts/nefertiti-uv.obj")"
echo "nefertiti exported: $v vertices, $f faces, $t texture coordinates ($u in [0,1]^2), $ft faces with them"
[ "$v" -eq 299 ] && [ "$f" -eq 562 ] && [ "$t" -eq 299 ] && [ "$u" -eq 299 ] && [ "$ft" -eq 562 ] ||
  fail "the exported face scan lacks a texture coordinate in [0,1]^2 per vertex"

# --- 3. the texture atlas of a closed mesh, shown with MeshLab's dummy checkerboard
cp "$checkout/third_party/real-meshes/pymeshlab-cow.obj" "$artifacts/cow.obj"
meshlab_on "$artifacts/cow.obj"
filter_dialog 14 "Ricci Flow: Conformal Parameterization"
# The focus reaches the first parameter after three Tabs; the target is the fifth parameter and
# the atlas its last choice; the colour ramp's box ten parameters on.
xdotool key Tab Tab Tab Tab Tab Tab Tab End
xdotool key Tab Tab Tab Tab Tab Tab Tab Tab Tab Tab space
sleep 0.5
import -window "$dialog" "$artifacts/dialog-atlas.png"
apply "Ricci Flow: Conformal Parameterization" 300 || fail "the atlas failed"
no_failure_dialog "the atlas"
grep -q "^LOG: 2 Ricci flow on cow.obj: closed genus-0 surface.*target atlas" "$log" ||
  fail "the dialog's target was not the atlas"
grep -Eq "^LOG: 2 Atlas: .* [0-9]+ charts? .* 0 overlapping faces" "$log" ||
  fail "the log has no atlas line, or the atlas overlaps"
close_dialog
import -window root "$artifacts/atlas.png"
# Set Texture, two entries below ours: the filename's field and its button, then "Use dummy
# texture"; the check size two fields on (32 texels: 16 squares a side).
filter_dialog 16 "Set Texture"
xdotool key Tab Tab Tab Tab Tab space Tab Tab ctrl+a
xdotool type "32"
apply "Set Texture" 60 || fail "Set Texture failed on the atlas"
no_failure_dialog "Set Texture"
close_dialog
import -window root "$artifacts/checkerboard.png"
expect_checkerboard "$artifacts/atlas.png" "$artifacts/checkerboard.png" 0.2
export_obj "$artifacts/cow-atlas.obj"
read -r v f t ft u <<<"$(obj_uv "$artifacts/cow-atlas.obj")"
echo "cow exported: $v vertices, $f faces, $t texture coordinates ($u in [0,1]^2), $ft faces with them"
[ "$f" -gt 0 ] && [ "$ft" -eq "$f" ] && [ "$t" -gt "$v" ] && [ "$u" -eq "$t" ] ||
  fail "the exported atlas lacks texture coordinates in [0,1]^2 on every face, cut at seams"

# --- 4. a Moebius strip: the failure shown, the mesh left as it was
awk 'BEGIN {
  n = 24; pi = atan2(0, -1); print "OFF"; print 2 * n, 2 * n, 0
  for (i = 0; i < n; i++) {
    t = 2 * pi * i / n
    for (s = -1; s <= 1; s += 2)
      printf "%.6f %.6f %.6f\n", (1 + 0.3 * s * cos(t / 2)) * cos(t), (1 + 0.3 * s * cos(t / 2)) * sin(t), 0.3 * s * sin(t / 2)
  }
  for (i = 0; i < n; i++) {
    a = 2 * i; b = 2 * i + 1; c = 2 * i + 2; d = 2 * i + 3
    if (i == n - 1) { c = 1; d = 0 }  # the half turn: the strip closes with its sides swapped
    print 3, a, b, c; print 3, b, d, c
  }
}' >"$artifacts/moebius.off"
meshlab_on "$artifacts/moebius.off"
filter_dialog 14 "Ricci Flow: Conformal Parameterization"
if apply "Ricci Flow: Conformal Parameterization" 60; then
  fail "the filter ran on a Moebius strip"
fi
box=$(visible "^Filter Failure$")
import -window root "$artifacts/failure-dialog.png"
xdotool windowfocus --sync "$box"
xdotool key Return
wait_log "failed: Ricci flow failed, the mesh is unchanged: " 30 ||
  fail "MeshLab's log has no failure of the filter"
grep -q "failed: Ricci flow failed, the mesh is unchanged: .*not orientable" "$log" ||
  fail "the failure does not say the mesh is not orientable"
click_dialog 1
sleep 0.5
export_obj "$artifacts/moebius-after.obj"
read -r v f t ft u <<<"$(obj_uv "$artifacts/moebius-after.obj")"
[ "$v" -eq 48 ] && [ "$f" -eq 48 ] && [ "$t" -eq 0 ] ||
  fail "the Moebius strip changed: $v vertices, $f faces, $t texture coordinates"
awk 'FNR == 1 { file++ }
     file == 1 && FNR > 2 && NF == 3 { x[++n] = $1; y[n] = $2; z[n] = $3 }
     file == 2 && /^v / { m++; d = ($2 - x[m])^2 + ($3 - y[m])^2 + ($4 - z[m])^2; if (d > 1e-10) bad++ }
     END { exit !(m == n && bad == 0) }' "$artifacts/moebius.off" "$artifacts/moebius-after.obj" ||
  fail "the Moebius strip's vertices moved"
echo "PASS: MeshLab 2025.07 GUI test; screenshots in $artifacts"
