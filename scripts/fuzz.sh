#!/usr/bin/env bash
# Builds the fuzz targets (tests/fuzz/) with clang, ASan and UBSan into build/fuzz; writes a seed
# corpus of small valid files of every format; runs every regression input (tests/fuzz/regressions)
# through the targets that read it; then fuzzes each target for SECONDS (default 60).
# Usage: fuzz.sh [SECONDS]. Exits non-zero on any crash, leak, timeout or memory past the limit.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
seconds=${1:-60}
build="$root/build/fuzz"
CXX=clang++-14 bash "$root/scripts/build.sh" fuzz -DCMAKE_BUILD_TYPE=Debug \
  -DCMAKE_CXX_COMPILER=clang++-14 -DRICCI_BUILD_FUZZERS=ON -DRICCI_BUILD_CLI=OFF \
  -DRICCI_BUILD_TESTS=OFF -DRICCI_WARNINGS_AS_ERRORS=ON
flags=(-timeout=10 -rss_limit_mb=2048)
export ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1

# --- seeds: a square (two triangles, or one quad) and a tetrahedron in every format
seeds="$build/seeds"
rm -rf "$seeds" && mkdir -p "$seeds"/{off,obj,ply,stl,gii}
printf 'OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n' >"$seeds/off/square.off"
printf 'OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n' >"$seeds/off/quad.off"
printf 'COFF\n# tetrahedron\n4 4 6\n0 0 0 1 0 0 1\n1 0 0 0 1 0 1\n0 1 0 0 0 1 1\n0 0 1 1 1 1 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n' \
  >"$seeds/off/tetrahedron.off"
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1\nf 1//1 3//1 4//1\n' \
  >"$seeds/obj/square.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\ng t\nusemtl m\nf -4 -2 -3\nf 1 2 4\nf 2 3 4\nf 1 4 3 \n' \
  >"$seeds/obj/tetrahedron.obj"
printf 'ply\nformat ascii 1.0\ncomment square\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0 1\n1 0 0 2\n1 1 0 3\n0 1 0 4\n3 0 1 2\n3 0 2 3\n' \
  >"$seeds/ply/square-ascii.ply"
python3 - "$seeds" <<'PY'
import struct, sys
seeds = sys.argv[1]
square = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
faces = [(0, 1, 2), (0, 2, 3)]
for order, name in (("<", "binary_little_endian"), (">", "binary_big_endian")):
    head = ("ply\nformat %s 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
            "property double z\nelement face 2\nproperty list uchar int vertex_indices\n"
            "end_header\n" % name).encode()
    body = b"".join(struct.pack(order + "3d", *p) for p in square)
    body += b"".join(struct.pack(order + "B3i", 3, *f) for f in faces)
    open("%s/ply/square-%s.ply" % (seeds, name), "wb").write(head + body)
stl = b"\0" * 80 + struct.pack("<I", 2)
for f in faces:
    stl += struct.pack("<3f", 0, 0, 1) + b"".join(struct.pack("<3f", *square[v]) for v in f) + b"\0\0"
open("%s/stl/square-binary.stl" % seeds, "wb").write(stl)
text = "solid square\n"
for f in faces:
    text += " facet normal 0 0 1\n  outer loop\n"
    text += "".join("   vertex %g %g %g\n" % square[v] for v in f)
    text += "  endloop\n endfacet\n"
open("%s/stl/square-ascii.stl" % seeds, "w").write(text + "endsolid square\n")
import base64, zlib
def gifti(encoding, points, triangles):
    head = ('<DataArray Intent="NIFTI_INTENT_%s" DataType="NIFTI_TYPE_%s" ArrayIndexingOrder='
            '"RowMajorOrder" Dimensionality="2" Dim0="%d" Dim1="3" Encoding="%s" Endian='
            '"LittleEndian">')
    body = ""
    for intent, kind, rows, fmt in (("POINTSET", "FLOAT32", points, "<3f"),
                                    ("TRIANGLE", "INT32", triangles, "<3i")):
        if encoding == "ASCII":
            data = " ".join("%g" % x for row in rows for x in row)
        else:
            raw = b"".join(struct.pack(fmt, *row) for row in rows)
            data = base64.b64encode(zlib.compress(raw) if encoding.startswith("GZip") else raw).decode()
        body += head % (intent, kind, len(rows), encoding) + "<Data>" + data + "</Data></DataArray>"
    return '<?xml version="1.0"?><GIFTI Version="1.0">' + body + "</GIFTI>\n"
for encoding in ("ASCII", "Base64Binary", "GZipBase64Binary"):
    open("%s/gii/square-%s.gii" % (seeds, encoding), "w").write(gifti(encoding, square, faces))
PY
mkdir -p "$seeds/all" && cp "$seeds"/{off,obj,ply,stl,gii}/* "$seeds/all/"

# --- the regression inputs, each through every target that reads it
regressions="$root/tests/fuzz/regressions"
for format in off obj ply stl gii; do
  inputs=("$regressions"/*."$format")
  [ -e "${inputs[0]}" ] || continue
  echo "fuzz: fuzz_read_$format on ${#inputs[@]} regression inputs"
  "$build/tests/fuzz/fuzz_read_$format" "${flags[@]}" "${inputs[@]}" >"$build/regressions-$format.log" 2>&1 ||
    { tail -n 40 "$build/regressions-$format.log"; exit 1; }
done
echo "fuzz: fuzz_read_and_repair on every regression input"
"$build/tests/fuzz/fuzz_read_and_repair" "${flags[@]}" "$regressions"/* \
  >"$build/regressions-all.log" 2>&1 || { tail -n 40 "$build/regressions-all.log"; exit 1; }

# --- each target for SECONDS, from its corpus (kept in build/fuzz between runs) and the seeds
cd "$build"
for target in off obj ply stl gii all; do
  name=fuzz_read_$target
  [ "$target" = all ] && name=fuzz_read_and_repair
  corpus="$build/corpus/$name"
  mkdir -p "$corpus"
  "$build/tests/fuzz/$name" "${flags[@]}" -max_total_time="$seconds" -print_final_stats=1 \
    "$corpus" "$seeds/$target" >"$build/$name.log" 2>&1 || { tail -n 60 "$build/$name.log"; exit 1; }
  echo "fuzz: $name for $seconds s: $(grep -o 'stat::number_of_executed_units: *[0-9]*' "$build/$name.log" |
    grep -o '[0-9]*$') executions, $(grep -o 'cov: [0-9]*' "$build/$name.log" | tail -1), no finding"
done
