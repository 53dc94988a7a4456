#!/bin/sh
# End-to-end checks of topodig view (src/cli/view.c; perspective views,
# paper 001 §2.6): a picture of the asked size from a real DEM in each
# style, the drape of an image, and bad input (one error line, exit 1, no
# output written).
BUILD=${BUILD:-build}
TD="$BUILD/topodig"
T=$(mktemp -d "${TMPDIR:-/tmp}/tdvw.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/util/e2e.sh # ok, bad, check, e2e_summary
pngsize() { od -An -tu1 -j16 -N8 "$1" | awk '{ print $1*16777216+$2*65536+$3*256+$4 "x" $5*16777216+$6*65536+$7*256+$8 }'; }
DEM=tests/data/dems/frontrange_srtm3.tif
[ -e "$DEM" ] || DEM=../shared/dems/frontrange_srtm3.tif

check "view --help" "$TD view --help | grep -q '^usage: topodig view'"
check "topodig lists view" "$TD --help 2>&1 | grep -q 'view'"
for s in shaded wire both; do
  "$TD" view "$DEM" -o "$T/$s.png" --style $s --size 640x480 2>"$T/err"
  check "--style $s: exit 0, one summary line, a 640 x 480 PNG" \
    "[ \$? = 0 ] && [ \$(grep -vc '^[a-z][a-z +]*: [0-9]*%\$' '$T/err') = 1 ] && [ \"\$(pngsize '$T/$s.png')\" = 640x480 ]"
done
"$TD" render "$DEM" -o "$T/shade.png" -q
"$TD" view "$DEM" -o "$T/drape.png" --drape tint -q
check "--drape tint: written" "[ -s '$T/drape.png' ]"
"$TD" view "$DEM" -o "$T/img.png" --drape "$T/shade.png" --light 90,30 --light 270,30 -q
check "--drape IMAGE with two lights: written" "[ -s '$T/img.png' ]"
check "the styles differ" "! cmp -s '$T/shaded.png' '$T/wire.png'"

"$TD" view "$DEM" -o "$T/spin.gif" --turntable 6 --size 160x120 2>"$T/err"
check "--turntable 6: exit 0, a looping GIF89a of 6 frames (160 x 120)" \
  "[ \$? = 0 ] && grep -q '6 views' '$T/err' && [ \"\$(head -c 6 '$T/spin.gif')\" = GIF89a ] && grep -q NETSCAPE2.0 '$T/spin.gif' && [ \$(od -An -tx1 -v '$T/spin.gif' | tr -s ' \\n' '  ' | grep -o '21 f9 04' | wc -l) -ge 6 ] && [ \"\$(od -An -tu1 -j6 -N4 '$T/spin.gif' | awk '{print \$1+256*\$2 \"x\" \$3+256*\$4}')\" = 160x120 ]"
"$TD" view "$DEM" -o "$T/spin.png" --turntable 6 2>"$T/err"
check "--turntable without a .gif: refused" "[ \$? = 1 ] && grep -q 'GIF' '$T/err' && [ ! -e '$T/spin.png' ]"

printf 'not a tiff' >"$T/bad.tif"
"$TD" view "$T/bad.tif" -o "$T/x.png" 2>"$T/err"
check "a corrupt DEM: one error naming it, exit 1, no output" \
  "[ \$? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'bad.tif' '$T/err' && [ ! -e '$T/x.png' ]"
"$TD" view "$DEM" -o "$T/x.png" --light 90,120 2>"$T/err"
check "a light above 90 degrees: refused" "[ \$? = 1 ] && grep -q 'altitude' '$T/err' && [ ! -e '$T/x.png' ]"
"$TD" view "$DEM" -o "$T/x.png" --drape "$T/missing.png" 2>"$T/err"
check "a missing drape image: one error naming it, exit 1" \
  "[ \$? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'missing.png' '$T/err' && [ ! -e '$T/x.png' ]"

e2e_summary
