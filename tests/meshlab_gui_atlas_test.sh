#!/usr/bin/env bash
# The texture atlas in the real MeshLab GUI under Xvfb, as a user makes one: the filter's target
# set to "Texture atlas" in its dialog (the u colour ramp unchecked), Apply; then MeshLab's own
# Filters > Texture > Set Texture, which runs only on a mesh with wedge texture coordinates and
# draws a checkerboard where the named image does not exist. The checkerboard must appear on the
# mesh: about half of it darkened (the grey squares), half as it was (the white ones).
# Usage (run by ctest under xvfb-run): meshlab_gui_atlas_test.sh PREFIX MESH.obj ARTIFACT_DIR
set -euo pipefail
prefix=$(realpath -m "$1") mesh=$(realpath -m "$2") artifacts=$(realpath -m "$3")
rm -rf "$artifacts"
mkdir -p "$artifacts"
source "$(dirname "$0")/meshlab/gui_lib.sh"

# MeshLab 2020.09's OBJ reader stops on an assertion with this cow (its face count check), so the
# test hands it the same triangles as OFF. Set Texture writes its checkerboard beside the mesh and
# MeshLab reads it back relative to its working directory: both are the artifact folder.
name=$(basename "$mesh" .obj)
awk '/^v /{v[++nv]=$2" "$3" "$4}
     /^f /{n=0; for(i=2;i<=NF;i++){split($i,a,"/"); c[++n]=a[1]-1}
           for(i=2;i<n;i++) f[++nf]="3 "c[1]" "c[i]" "c[i+1]}
     END{print "OFF"; print nv, nf, 0; for(i=1;i<=nv;i++) print v[i]; for(i=1;i<=nf;i++) print f[i]}' \
  "$mesh" >"$artifacts/$name.off"
cd "$artifacts"

start_meshlab "$prefix" "$artifacts/$name.off"

# The dialog opens with the keyboard focus three Tabs before its first parameter; the target is
# the fifth parameter and the atlas its last choice; the colour ramp's box ten parameters on.
open_texture_filter 14 "Ricci Flow: Conformal Parameterization"
xdotool key Tab Tab Tab Tab Tab Tab Tab End
xdotool key Tab Tab Tab Tab Tab Tab Tab Tab Tab Tab space
sleep 1
import -window root "$artifacts/dialog-atlas.png"
apply_and_close 10
no_failure_dialog "the atlas"
import -window root "$artifacts/atlas.png"

# Set Texture is two entries below ours.
open_texture_filter 16 "Set Texture"
apply_and_close 4
no_failure_dialog "Set Texture"
import -window root "$artifacts/checkerboard.png"
[ -f "$artifacts/$name.png" ] ||
  fail "Set Texture made no checkerboard: the mesh had no wedge texture coordinates"

expect_checkerboard "$artifacts/atlas.png" "$artifacts/checkerboard.png" 0.25
echo "PASS: MeshLab GUI atlas test; screenshots in $artifacts"
