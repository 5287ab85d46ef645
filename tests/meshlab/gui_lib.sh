# Sourced by the MeshLab GUI tests (run under xvfb-run): MeshLab started on a mesh, and the steps
# that drive it with xdotool. The caller sets `artifacts` (the screenshots' folder) first.

# Stops the test with a screenshot of the whole screen.
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

# start_meshlab PREFIX MESH: MeshLab on MESH, its window 1280x1000 and focused; sets `main`.
# MeshLab is stopped when the test exits.
start_meshlab() {
  "$1/bin/meshlab" "$2" >"$artifacts/meshlab-gui.log" 2>&1 &
  meshlab_pid=$!
  trap 'kill $meshlab_pid 2>/dev/null || true' EXIT
  main=$(wait_window "^MeshLab" 60) || fail "MeshLab's window did not appear"
  xdotool windowsize "$main" 1280 1000
  xdotool windowfocus --sync "$main"
  sleep 2
}

# open_texture_filter N NAME: Filters (Alt+L) > Texture (second from the bottom) > the N-th
# entry, whose dialog is titled NAME; sets `dialog`. Debian's MeshLab 2020.09 lists the Texture
# submenu alphabetically.
open_texture_filter() {
  xdotool windowfocus --sync "$main"
  xdotool key alt+l
  sleep 1
  xdotool key Up Up Right
  sleep 1
  for _ in $(seq $(($1 - 1))); do xdotool key Down; done
  xdotool key Return
  dialog=$(wait_window "^$2\$" 20) || fail "the dialog of '$2' did not open from Filters > Texture"
  sleep 1
}

# Apply (the dialog's bottom-right button), waiting $1 seconds, then Close (bottom-left).
apply_and_close() {
  eval "$(xdotool getwindowgeometry --shell "$dialog")"
  xdotool mousemove --window "$dialog" $((WIDTH * 3 / 4)) $((HEIGHT - 22)) click 1
  sleep "$1"
  xdotool mousemove --window "$dialog" $((WIDTH / 4)) $((HEIGHT - 22)) click 1
  sleep 2
}

# Fails when MeshLab shows a filter's failure ("Filter Failure", "PreConditions' Failure").
no_failure_dialog() {
  if wait_window "Failure" 1 >/dev/null; then
    fail "$1: MeshLab shows a failure dialog"
  fi
}

# The 3D view of a screenshot of the 1280x1000 main window, as MIFF on standard output.
view_of() {
  convert "$1" -crop 840x760+10+80 +repage miff:-
}

# Shares of the mesh's pixels (the view's grey ones) that the texture darkens and that it leaves
# as they were: a checkerboard of grey and white squares, modulating the shading, gives about
# half each; no texture gives none darkened.
two_tones() {
  view_of "$1" >"$artifacts/plain.miff"
  view_of "$2" >"$artifacts/textured.miff"
  (
    cd "$artifacts"
    convert plain.miff -colorspace HSL -channel G -separate +channel -threshold 12% -negate \
      mesh.miff
    mesh=$(convert mesh.miff -format "%[fx:mean]" info:)
    darker=$(convert plain.miff textured.miff -fx "(u.intensity - v.intensity > 0.12) ? 1 : 0" \
      mesh.miff -compose Multiply -composite -format "%[fx:mean]" info:)
    same=$(convert plain.miff textured.miff -fx "abs(u.intensity - v.intensity) < 0.04 ? 1 : 0" \
      mesh.miff -compose Multiply -composite -format "%[fx:mean]" info:)
    rm -f plain.miff textured.miff mesh.miff
    awk -v m="$mesh" -v d="$darker" -v s="$same" \
      'BEGIN { if (m > 0) printf "%.3f %.3f %.4f\n", d / m, s / m, m; else print "0 0 0" }'
  )
}

# expect_checkerboard BEFORE AFTER SHARE: the mesh (more than 2 % of the view) has more than
# SHARE of its pixels darkened and more than SHARE unchanged from screenshot BEFORE to AFTER.
expect_checkerboard() {
  local tones darker same mesh
  tones=$(two_tones "$1" "$2") || fail "the screenshots could not be compared"
  read -r darker same mesh <<<"$tones"
  echo "the mesh covers $mesh of the view; the texture darkens $darker of it and leaves $same"
  awk -v d="$darker" -v s="$same" -v m="$mesh" -v x="$3" \
    'BEGIN { exit !(m > 0.02 && d > x && s > x) }' ||
    fail "no checkerboard on the mesh (darkened $darker, unchanged $same of the mesh's pixels)"
}
