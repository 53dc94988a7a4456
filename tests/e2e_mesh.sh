#!/bin/sh
# End-to-end checks of topodig mesh (src/cli/mesh.c, src/mesh): a real DEM
# to a binary STL that admesh finds closed (one part, nothing to fix, no
# backwards edges), to OBJ (with a texture), PLY and glTF binary that
# assimp loads with the triangles the summary names; bad input (one error
# line, exit 1, no output written).
BUILD=${BUILD:-build}
TD="$BUILD/topodig"
T=$(mktemp -d "${TMPDIR:-/tmp}/tdms.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/util/e2e.sh # ok, bad, check, e2e_summary
DEM=tests/data/dems/elkhorn_srtm3.tif
[ -e "$DEM" ] || DEM=../shared/dems/elkhorn_srtm3.tif

check "mesh --help" "$TD mesh --help | grep -q '^usage: topodig mesh'"
"$TD" mesh "$DEM" -o "$T/m.stl" --print-size 150 --exaggeration 10 --base 3 2>"$T/err"
check "STL: exit 0, one summary line, 150 mm long" \
  "[ \$? = 0 ] && [ \$(grep -vc '^[a-z][a-z +]*: [0-9]*%\$' '$T/err') = 1 ] && grep -q '150 x [0-9.]* x [0-9.]* mm' '$T/err'"
nt=$(sed -n 's/.* \([0-9]*\) triangles.*/\1/p' "$T/err")
check "STL: 84 + 50 bytes a triangle" "[ \$(wc -c <'$T/m.stl') = \$((84 + 50 * $nt)) ]"
if command -v admesh >/dev/null 2>&1; then
  admesh "$T/m.stl" >"$T/admesh.txt" 2>&1
  check "admesh: one part, no degenerate facet, nothing fixed, no backwards edge" \
    "grep -Eq 'Number of parts +: +1 ' '$T/admesh.txt' && grep -Eq 'Degenerate facets +: +0' '$T/admesh.txt' && grep -Eq 'Edges fixed +: +0' '$T/admesh.txt' && grep -Eq 'Facets reversed +: +0' '$T/admesh.txt' && grep -Eq 'Backwards edges +: +0' '$T/admesh.txt'"
fi
"$TD" render "$DEM" -o "$T/map.png" --style tint --contours 20 -q
"$TD" mesh "$DEM" -o "$T/m.obj" --step 2 --texture "$T/map.png" 2>"$T/err"
nt=$(sed -n 's/.* \([0-9]*\) triangles.*/\1/p' "$T/err")
check "OBJ with a texture: the .mtl and the texture beside it" \
  "[ -s '$T/m.mtl' ] && [ -s '$T/m_texture.png' ] && grep -q 'map_Kd m_texture.png' '$T/m.mtl' && grep -q '^mtllib m.mtl' '$T/m.obj'"
"$TD" mesh "$DEM" -o "$T/m.ply" --step 2 -q
"$TD" mesh "$DEM" -o "$T/m.glb" --step 2 -q
if command -v assimp >/dev/null 2>&1; then
  for f in obj ply glb; do
    assimp info "$T/m.$f" >"$T/ai.txt" 2>&1
    check "assimp loads the .$f: $nt faces" "grep -Eq '^Faces: +$nt\$' '$T/ai.txt'"
  done
fi

printf 'ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value -9999\n-9999 -9999 -9999\n-9999 -9999 -9999\n-9999 -9999 -9999\n' >"$T/empty.asc"
"$TD" mesh "$T/empty.asc" -o "$T/x.stl" 2>"$T/err"
check "a DEM all nodata: one error naming it, exit 1, no output" \
  "[ \$? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'empty.asc' '$T/err' && [ ! -e '$T/x.stl' ]"
printf 'ncols 1\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\n1\n2\n3\n' >"$T/thin.asc"
"$TD" mesh "$T/thin.asc" -o "$T/x.stl" 2>"$T/err"
check "a DEM 1 cell wide: one error, exit 1" "[ \$? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && [ ! -e '$T/x.stl' ]"
"$TD" mesh "$DEM" -o "$T/x.dae" 2>"$T/err"
check "an unknown format: one error naming the formats, exit 1" \
  "[ \$? = 1 ] && grep -q '.stl, .obj, .ply, .glb' '$T/err' && [ ! -e '$T/x.dae' ]"
"$TD" mesh "$DEM" -o "$T/x.stl" --texture "$T/map.png" 2>"$T/err"
check "a texture for an STL: refused" "[ \$? = 1 ] && grep -q 'texture' '$T/err' && [ ! -e '$T/x.stl' ]"

e2e_summary
