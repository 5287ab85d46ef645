#!/usr/bin/env bash
# The demo: set up, build, and flatten a bundled face scan (a disk) into the plane with the
# defaults (Yamabe flow, the auto target: a disk goes onto the unit disk). Writes the result
# mesh, a picture of the layout
# and a JSON report into out/demo/.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bash "$root/scripts/setup.sh"
bash "$root/scripts/build.sh" release -DCMAKE_BUILD_TYPE=Release -DRICCI_BUILD_TESTS=OFF
out="$root/out/demo"
mkdir -p "$out"
"$root/build/release/cli/ricci-flow" "$root/meshes/nefertiti.off" \
  -o "$out/nefertiti-flat.ply" --picture "$out/nefertiti-layout.png" \
  --report "$out/nefertiti-report.json"
echo
echo "result mesh (open it in MeshLab; its UVs are the flat layout): $out/nefertiti-flat.ply"
echo "picture of the layout (coloured by the conformal factor u):   $out/nefertiti-layout.png"
echo "convergence history, timings and errors:                      $out/nefertiti-report.json"
