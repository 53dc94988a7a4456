#!/bin/sh
# End-to-end checks of the CLI contract through build/topodig: help,
# summary line, outputs other tools open, and bad input (one error line,
# exit 1, no output left, an existing output untouched).  Covers the option
# layer (src/cli/opt.c, src/cli/opt_help.c) and src/cli/cli.c.
BUILD=${BUILD:-build}
TD="$BUILD/topodig"
T=$(mktemp -d "${TMPDIR:-/tmp}/tde2e.XXXXXX")
trap 'rm -rf "$T"' EXIT
pass=0; fail=0
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; }
check() { if eval "$2"; then ok "$1"; else bad "$1"; fi; }

# --- help and version
check "topodig --help exits 0" "$TD --help >/dev/null"
check "topodig --version" "$TD --version | grep -q '^topodig [0-9]'"
check "scan --help lists --ink" "$TD scan --help | grep -q -- '--ink'"
check "unknown command: exit 1" "! $TD frobnicate 2>/dev/null"

# --- a real run on the grey sample sheet
"$TD" scan samples/hills.png -o "$T/hills.geojson" --debug-dir "$T/dbg" 2>"$T/err"
rc=$?
check "scan sample: exit 0" "[ $rc = 0 ]"
check "scan sample: one summary line" \
  "[ \$(grep -vc '^[a-z][a-z +]*: [0-9]*%\$' '$T/err') = 1 ] && grep -Eq '^scan: [0-9]+ lines, [0-9]+ closed, [0-9]+ open, [0-9]+ edge, [0-9]+ bridged gaps, [0-9]+ remaining junctions, [0-9]+ merges resolved, [0-9]+ left open, [0-9.]+ s$' '$T/err'"
nlines=$(sed -n 's/^scan: \([0-9]*\) lines.*/\1/p' "$T/err")
check "scan sample: GeoJSON has one feature per line" \
  "[ \"\$(grep -o '\"type\": *\"Feature\"' '$T/hills.geojson' | wc -l)\" = '$nlines' ]"
for f in mask skeleton despurred overlay; do
  check "debug picture $f.png written" "[ -s '$T/dbg/$f.png' ]"
done
if command -v ogrinfo >/dev/null 2>&1; then
  check "ogrinfo opens the lines ($nlines features)" \
    "ogrinfo -ro -al -so '$T/hills.geojson' 2>/dev/null | grep -q 'Feature Count: $nlines'"
fi
if command -v gdalinfo >/dev/null 2>&1; then
  size=$(gdalinfo samples/hills.png 2>/dev/null | sed -n 's/^Size is //p')
  check "gdalinfo opens overlay.png, scan's size" \
    "gdalinfo '$T/dbg/overlay.png' 2>/dev/null | grep -q 'Size is $size'"
fi
# --- the same sheet in other layouts gives the same contours
if command -v gdal_translate >/dev/null 2>&1; then
  gdal_translate -q -co TILED=YES -co COMPRESS=LZW samples/hills.png "$T/tiled.tif"
  gdal_translate -q -scale 0 255 0 1 -ot Byte -co NBITS=1 -co COMPRESS=CCITTFAX4 samples/hills.png "$T/g4.tif"
  gdal_translate -q -of JPEG -co QUALITY=85 samples/hills.png "$T/sheet.jpg"
  for f in tiled.tif g4.tif sheet.jpg; do
    "$TD" scan "$T/$f" -o "$T/$f.geojson" 2>"$T/err.$f"
    n=$(sed -n 's/^scan: \([0-9]*\) lines.*/\1/p' "$T/err.$f")
    check "$f (tiled LZW / 1-bit G4 / JPEG): $n lines, as from the PNG" "[ '$n' = '$nlines' ]"
  done
fi
check "no temporary files left" "! ls '$T' '$T/dbg' | grep -q '\.tmp\.'"

# --- a fresh generated sheet (tdgen) scans into as many lines as its truth
if [ -x "$BUILD/tdgen" ]; then
  "$BUILD/tdgen" -o "$T/gen.png" --truth "$T/gen.geojson" --size 400x300 --seed 3 \
      --width 3 --breaks 4 --quiet
  ntruth=$(grep -o '"type": *"Feature"' "$T/gen.geojson" | wc -l)
  "$TD" scan "$T/gen.png" -o "$T/gen_lines.geojson" 2>"$T/err"
  ngen=$(sed -n 's/^scan: \([0-9]*\) lines.*/\1/p' "$T/err")
  check "tdgen sheet: $ngen traced lines for $ntruth true contours" \
    "[ '$ntruth' -gt 5 ] && [ '$ngen' = '$ntruth' ]"
fi

# --- the labeller refuses: one error line (progress lines of a slow run
# aside), no DEM, and --debug-dir shows the labels read (a hills sheet with
# two printed labels: too few to infer the interval from)
if [ -x "$BUILD/tdgen" ]; then
  "$BUILD/tdgen" --terrain hills --size 700 --labels 1 --label-font dejavu \
      --seed 3 -o "$T/two.png" --quiet
  "$TD" run "$T/two.png" -o "$T/two.tif" --debug-dir "$T/tdbg" -q 2>"$T/err"
  rc=$?
  check "run refused: exit 1, one line naming --interval, no DEM" \
    "[ $rc = 1 ] && [ \"\$(grep -vc '^[a-z][a-z +]*: [0-9]*%\$' '$T/err')\" = 1 ] && grep -q -- '--interval' '$T/err' && [ ! -e '$T/two.tif' ]"
  check "run refused: --debug-dir has the 2 labels read and heights.png" \
    "[ \"\$(grep -o '\"confidence\"' '$T/tdbg/labels.geojson' | wc -l)\" = 2 ] && [ -s '$T/tdbg/heights.png' ]"
  "$TD" scan "$T/two.png" -o "$T/two.geojson" -q
  "$TD" label "$T/two.geojson" --sheet "$T/two.png" -o "$T/two_l.geojson" \
      --debug-dir "$T/ldbg" -q 2>"$T/err"
  rc=$?
  check "label refused: exit 1, one line, no output, labels.geojson" \
    "[ $rc = 1 ] && [ \"\$(grep -vc '^[a-z][a-z +]*: [0-9]*%\$' '$T/err')\" = 1 ] && [ ! -e '$T/two_l.geojson' ] && [ \"\$(grep -o '\"confidence\"' '$T/ldbg/labels.geojson' | wc -l)\" = 2 ]"
fi

# --- bad input: one line on stderr, exit 1, nothing written
expect_fail() { # name, input file, extra args
  name=$1; in=$2; shift 2
  rm -f "$T/out.geojson"
  "$TD" scan "$in" -o "$T/out.geojson" "$@" 2>"$T/err"
  rc=$?
  if [ $rc = 1 ] && [ "$(wc -l <"$T/err")" = 1 ] && [ ! -e "$T/out.geojson" ] &&
     ! ls "$T" | grep -q '\.tmp\.'; then
    ok "$name: $(cat "$T/err")"
  else
    bad "$name (exit $rc, stderr: $(cat "$T/err"))"
  fi
}
echo "this is not an image" >"$T/text.png"
expect_fail "text file named .png" "$T/text.png"
head -c 300 samples/hills.png >"$T/trunc.png"
expect_fail "truncated PNG" "$T/trunc.png"
: >"$T/empty.tif"
expect_fail "empty file" "$T/empty.tif"
expect_fail "missing file" "$T/nope.tif"
# little-endian TIFF headers: 9 tags, 8-bit grey, one strip
tiff() { # width-bytes height-bytes bits extra-entry count
  printf '\111\111\052\000\010\000\000\000'"$5"'\000'
  printf '\000\001\004\000\001\000\000\000'"$1"
  printf '\001\001\004\000\001\000\000\000'"$2"
  printf '\002\001\003\000\001\000\000\000'"$3"'\000\000\000'
  printf '\003\001\003\000\001\000\000\000\001\000\000\000'
  printf '\006\001\003\000\001\000\000\000\001\000\000\000'
  printf '\021\001\004\000\001\000\000\000\010\000\000\000'
  printf '\025\001\003\000\001\000\000\000\001\000\000\000'
  printf '\026\001\004\000\001\000\000\000'"$2"
  printf '\027\001\004\000\001\000\000\000\020\000\000\000'
  printf "$4"
  printf '\000\000\000\000'
}
tiff '\240\206\001\000' '\240\206\001\000' '\010' '' '\011' >"$T/huge.tif"
expect_fail "100000x100000 TIFF header" "$T/huge.tif"
tiff '\000\000\000\000' '\004\000\000\000' '\010' '' '\011' >"$T/zero.tif"
expect_fail "zero-width TIFF" "$T/zero.tif"
tiff '\004\000\000\000' '\004\000\000\000' '\040' '\123\001\003\000\001\000\000\000\003\000\000\000' '\012' >"$T/float.tif"
expect_fail "float samples (a DEM, not a scan)" "$T/float.tif"
expect_fail "bad --ink value" samples/hills.png --ink purple
expect_fail "bad --threshold value" samples/hills.png --threshold 300
expect_fail "unknown option" samples/hills.png --frobnicate
check "missing -o: exit 1" "! $TD scan samples/hills.png 2>/dev/null"

# --- a failed run leaves an existing output untouched
echo keep >"$T/keep.geojson"
"$TD" scan "$T/text.png" -o "$T/keep.geojson" 2>/dev/null
check "failed run leaves existing output untouched" "[ \"\$(cat '$T/keep.geojson')\" = keep ]"

# --- outputs that must not do harm (issue 15's catalogue, regression tests)
echo precious >"$T/victim"
sh -c 'ln -s "$1/victim" "$1/out.png.tmp.$$.0"; ln -s "$1/victim" "$1/out.png.tmp.$$"; exec "$2" render samples/hills.tif -o "$1/out.png"' sh "$T" "$TD" 2>/dev/null
check "a symlink planted at the temporary name is not followed" \
  "[ \"\$(cat '$T/victim')\" = precious ] && [ -s '$T/out.png' ] && [ ! -L '$T/out.png' ]"
rm -f "$T"/out.png.tmp.*
if mkfifo "$T/fifo" 2>/dev/null; then
  "$TD" render samples/hills.tif -o "$T/fifo" 2>"$T/err"
  check "-o a FIFO: exit 1, one line naming it, still a FIFO" \
    "[ \$? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'fifo: is a FIFO' '$T/err' && [ -p '$T/fifo' ]"
fi
"$TD" render samples/hills.tif -o "$T" 2>"$T/err"
check "-o a folder: exit 1, one line" "[ \$? = 1 ] && grep -q 'is a folder' '$T/err'"
cp samples/hills.tif "$T/h.tif"
for cmd in "render" "flow" "erode --steps 1"; do
  "$TD" $cmd "$T/h.tif" -o "$T/h.tif" 2>"$T/err"
  check "$cmd -o the input: exit 1, the input untouched" \
    "[ \$? = 1 ] && grep -q 'the output is the input' '$T/err' && cmp -s samples/hills.tif '$T/h.tif'"
done
cp samples/hills.png "$T/s.png"
ln -s s.png "$T/s_link.png"
"$TD" scan "$T/s.png" -o "$T/s_link.png" 2>"$T/err"
check "scan -o the scan (through a link): exit 1, the scan untouched" \
  "[ \$? = 1 ] && grep -q 'the output is the input' '$T/err' && cmp -s samples/hills.png '$T/s.png'"
echo old >"$T/p.tif"
"$TD" flow samples/hills.tif -o "$T/p.tif" --classes /nonexistent/c.tif -q 2>/dev/null
check "flow: a failed --classes leaves the existing output as it was" \
  "[ \$? = 1 ] && [ \"\$(cat '$T/p.tif')\" = old ]"
"$TD" run samples/hills.png -o "$T/nan.tif" --interval 20 --known 123.5,264,nan 2>"$T/err"
check "run --known X,Y,nan: exit 1, one line, no output" \
  "[ \$? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'is not X,Y,H' '$T/err' && [ ! -e '$T/nan.tif' ]"
for v in inf 1e400 -nan; do
  "$TD" label samples/hills.geojson -o "$T/k.geojson" --interval 20 --known "10,10,$v" 2>/dev/null
  check "label --known 10,10,$v: exit 1, no output" "[ \$? = 1 ] && [ ! -e '$T/k.geojson' ]"
done

# a line whose coordinates run to 300000: memory follows the lines (1 GB
# of address space is plenty), not the extent they claim (it took 11 GB)
printf '{"type":"FeatureCollection","features":[{"type":"Feature","properties":{},"geometry":{"type":"LineString","coordinates":[[10,10],[300000,10],[300000,300000]]}}]}' >"$T/far.geojson"
case "$BUILD" in
*san*) ;; # the sanitisers reserve terabytes of address space
*)
  (ulimit -v 1000000; "$TD" label "$T/far.geojson" -o "$T/far_l.geojson" --interval 20 --known 10,10,100 -q)
  check "label of a line to 300000 px within 1 GB: exit 0, labelled" \
    "[ \$? = 0 ] && grep -q '\"height\":100' '$T/far_l.geojson'"
  ;;
esac

# coordinates and heights that would overflow
printf '{"type":"FeatureCollection","features":[{"type":"Feature","properties":{},"geometry":{"type":"LineString","coordinates":[[10,10],[1e308,10]]}}]}' >"$T/huge.geojson"
"$TD" label "$T/huge.geojson" -o "$T/hk.geojson" --interval 20 --known 10,10,100 2>"$T/err"
check "label of a line to x = 1e308: exit 1, one line, no output" \
  "[ \$? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'beyond any sheet' '$T/err' && [ ! -e '$T/hk.geojson' ]"
"$TD" label samples/hills.geojson -o "$T/hk.geojson" --interval 1e-9 --known 123.5,264,1e12 2>"$T/err"
check "label --interval 1e-9 --known ..,1e12: exit 1, one line naming --interval" \
  "[ \$? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'check --interval' '$T/err' && [ ! -e '$T/hk.geojson' ]"

# a folder as an input is named as one (it was "empty file", or read as an
# empty --known-file with exit 0)
mkdir -p "$T/adir"
"$TD" scan "$T/adir" -o "$T/d.geojson" 2>"$T/err"
check "scan FOLDER: exit 1, 'is a folder'" "[ \$? = 1 ] && grep -q 'adir: is a folder' '$T/err'"
"$TD" label samples/hills.geojson -o "$T/d.geojson" --interval 20 --known-file "$T/adir" 2>"$T/err"
check "label --known-file FOLDER: exit 1, no output" \
  "[ \$? = 1 ] && grep -q 'adir: is a folder' '$T/err' && [ ! -e '$T/d.geojson' ]"
"$TD" render "$T/adir" -o "$T/d.png" 2>"$T/err"
check "render FOLDER: exit 1, 'is a folder'" "[ \$? = 1 ] && grep -q 'adir: is a folder' '$T/err'"
# compare: no cell with data in both is an error, not rmse 0; an ASCII
# grid with more values than its header says is refused
printf 'ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value -9999\n-9999 -9999\n-9999 -9999\n' >"$T/nd.asc"
printf 'ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value -9999\n1 2\n3 4\n' >"$T/v.asc"
printf 'ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value -9999\n1 2\n3 4\n5\n' >"$T/x.asc"
"$TD" compare "$T/nd.asc" "$T/v.asc" >/dev/null 2>"$T/err"
check "compare with no common cell: exit 1, one line" \
  "[ \$? = 1 ] && grep -q 'no cell with data in both' '$T/err'"
"$TD" compare "$T/x.asc" "$T/v.asc" >/dev/null 2>"$T/err"
check "an ASCII grid with an extra value: exit 1, naming the line" \
  "[ \$? = 1 ] && grep -q 'x.asc: line 9: more than the 4 values' '$T/err'"

echo "$pass passed, $fail failed"
[ $fail = 0 ]
