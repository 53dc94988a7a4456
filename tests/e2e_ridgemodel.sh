#!/bin/sh
# End-to-end checks of topodig ridgemodel (src/cli/ridgemodel.c; the
# ridgeline model, paper 000 §2.1-2.4): heights of a 3-D ridge read back
# from the DEM at known cells, a 2-D tree's node heights (Algorithm 2.4),
# the ridge lines of 'topodig ridges' taken as they are (valleys skipped),
# the recursive generation (2.5) repeatable by its seed,
# edits applied by both deletion algorithms equal to a model of the final
# segments, and bad input (one error line, exit 1, no output written).
BUILD=${BUILD:-build}
TD="$BUILD/topodig"
T=$(mktemp -d "${TMPDIR:-/tmp}/tdrm.XXXXXX")
trap 'rm -rf "$T"' EXIT
pass=0; fail=0
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; }
check() { if eval "$2"; then ok "$1"; else bad "$1"; fi; }
. tests/util/e2e.sh # near, at

check "ridgemodel --help" "$TD ridgemodel --help | grep -q '^usage: topodig ridgemodel'"
check "topodig lists ridgemodel" "$TD --help 2>&1 | grep -q ridgemodel"

# --- a level ridge at 100 from (50,100) to (150,100), slope 45 (1 per cell)
cat >"$T/r.geojson" <<'EOF'
{"type":"FeatureCollection","features":[
{"type":"Feature","properties":{},"geometry":{"type":"LineString","coordinates":[[50,-100,100],[150,-100,100]]}}]}
EOF
"$TD" ridgemodel "$T/r.geojson" -o "$T/r.tif" --size 200x200 --slope 45 --smooth 0 2>"$T/err"
rc=$?
check "3-D ridge: exit 0, one summary line" \
  "[ $rc = 0 ] && [ \$(grep -vc '^[a-z][a-z +]*: [0-9]*%\$' '$T/err') = 1 ] && grep -q '^ridgemodel: 1 segments, 2 nodes, 200 x 200 cells' '$T/err'"
if command -v gdallocationinfo >/dev/null 2>&1; then
  check "3-D ridge: 30.5 cells below it, 100 - 30.5" "near '$(at "$T/r.tif" 100 130)' 69.5 0.01"
  check "3-D ridge: on it, 100 - 0.5" "near '$(at "$T/r.tif" 100 100)' 99.5 0.01"
  check "3-D ridge: beyond the skirts, the base 0" "near '$(at "$T/r.tif" 0 0)' 0 0"
fi

# --- a 2-D tree: leaves at 50, the fork at 50 + tan(45) x 100
cat >"$T/t.geojson" <<'EOF'
{"type":"FeatureCollection","features":[
{"type":"Feature","properties":{},"geometry":{"type":"LineString","coordinates":[[20,-100],[120,-100],[220,-100]]}},
{"type":"Feature","properties":{},"geometry":{"type":"LineString","coordinates":[[120,-100],[120,-230]]}}]}
EOF
"$TD" ridgemodel "$T/t.geojson" -o "$T/t.tif" --size 240x240 --slope 45 --leaf-height 50 --nodes-out "$T/n.geojson" -q
rc=$?
check "2-D tree: exit 0, 4 nodes written" "[ $rc = 0 ] && [ \$(grep -o '\"Point\"' '$T/n.geojson' | wc -l) = 4 ]"
check "2-D tree: the fork at 150, the leaves at 50" \
  "grep -q '\"height\": 150}.*\"coordinates\": \[120, -100, 150\]' '$T/n.geojson' && [ \$(grep -c '\"height\": 50}' '$T/n.geojson') = 3 ]"
"$TD" ridgemodel "$T/t.geojson" -o "$T/t0.tif" --size 240x240 2>"$T/err"
check "2-D lines without --leaf-height: one error naming the file" \
  "[ $? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 't.geojson.*without a height.*--leaf-height' '$T/err' && [ ! -e '$T/t0.tif' ]"

# --- Algorithm 2.5: rounds of generated ridges, the same for the same seed
"$TD" ridgemodel "$T/t.geojson" -o "$T/g1.tif" --size 240x240 --leaf-height 50 --generate 2 --seed 5 2>"$T/err"
rc=$?
check "--generate 2: exit 0, more segments, final slope 50" \
  "[ $rc = 0 ] && grep -Eq '^ridgemodel: [0-9]{2,} segments.*2 rounds generated, final slope 50' '$T/err'"
"$TD" ridgemodel "$T/t.geojson" -o "$T/g2.tif" --size 240x240 --leaf-height 50 --generate 2 --seed 5 -q
"$TD" ridgemodel "$T/t.geojson" -o "$T/g3.tif" --size 240x240 --leaf-height 50 --generate 2 --seed 6 -q
check "--generate: the same seed, the same DEM; another seed, another" \
  "cmp -s '$T/g1.tif' '$T/g2.tif' && ! cmp -s '$T/g1.tif' '$T/g3.tif'"

# --- the ridges of the sample sheet, taken as they are
"$TD" ridges samples/hills.geojson -o "$T/hr.geojson" -q
nr=$(grep -o '"kind":"ridge"' "$T/hr.geojson" | wc -l)
"$TD" ridgemodel "$T/hr.geojson" -o "$T/hm.tif" --like samples/hills.png --slope 20 2>"$T/err"
rc=$?
check "sample's ridges ($nr ridge lines): exit 0, DEM written" "[ $rc = 0 ] && [ -s '$T/hm.tif' ]"
"$TD" compare "$T/hm.tif" samples/hills.tif --json >"$T/hm.json"
check "sample's ridge model compares with the true DEM" "grep -q '\"rmse\"' '$T/hm.json'"

# --- edits: both deletion algorithms end where a model of the final set is
cat >"$T/e3.geojson" <<'EOF'
{"type":"FeatureCollection","features":[
{"type":"Feature","properties":{},"geometry":{"type":"LineString","coordinates":[[20,-20,80],[80,-60,120],[150,-40,90]]}},
{"type":"Feature","properties":{},"geometry":{"type":"LineString","coordinates":[[80,-60,120],[90,-150,70]]}}]}
EOF
cat >"$T/final.geojson" <<'EOF'
{"type":"FeatureCollection","features":[
{"type":"Feature","properties":{},"geometry":{"type":"LineString","coordinates":[[20,-20,80],[80,-60,120],[90,-150,70]]}},
{"type":"Feature","properties":{},"geometry":{"type":"LineString","coordinates":[[80,-60,120],[170,-120,60]]}}]}
EOF
cat >"$T/edits.txt" <<'EOF'
# drop the east arm, add one to the south-east
delete 80 -60 150 -40
add 80 -60 120 170 -120 60
EOF
"$TD" ridgemodel "$T/final.geojson" -o "$T/f.tif" --size 200x180 --slope 30 -q
for m in lists winners; do
  "$TD" ridgemodel "$T/e3.geojson" -o "$T/e_$m.tif" --size 200x180 --slope 30 --edits "$T/edits.txt" --delete-method $m 2>"$T/err"
  rc=$?
  "$TD" compare "$T/e_$m.tif" "$T/f.tif" --json >"$T/c.json"
  check "edits by $m: exit 0, 1 added 1 deleted, equal to the final model" \
    "[ $rc = 0 ] && grep -q 'edits: 1 added, 1 deleted ($m' '$T/err' && grep -q '\"max_abs\": *0[,}]' '$T/c.json'"
done

# --- bad input
cat >"$T/cyc.geojson" <<'EOF'
{"type":"FeatureCollection","features":[
{"type":"Feature","properties":{},"geometry":{"type":"LineString","coordinates":[[10,-10],[50,-10],[50,-50],[10,-10]]}}]}
EOF
"$TD" ridgemodel "$T/cyc.geojson" -o "$T/x.tif" --size 60x60 --leaf-height 0 2>"$T/err"
check "a cycle: one error line, exit 1, no output" \
  "[ $? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'not a tree' '$T/err' && [ ! -e '$T/x.tif' ]"
"$TD" ridgemodel "$T/r.geojson" -o "$T/x.tif" 2>"$T/err"
check "no grid: one error line, exit 1" "[ $? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'size' '$T/err'"
cat >"$T/far.geojson" <<'EOT'
{"type":"FeatureCollection","features":[
{"type":"Feature","properties":{},"geometry":{"type":"LineString","coordinates":[[5000,-5000,100],[6000,-5000,100]]}}]}
EOT
"$TD" ridgemodel "$T/far.geojson" -o "$T/far.tif" --size 200x200 --slope 30 2>"$T/err"
check "ridge lines all off the grid: one error naming the file, exit 1, no output" \
  "[ \$? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'far.geojson: no ridge line lies on the 200 x 200 grid' '$T/err' && [ ! -e '$T/far.tif' ]"
printf 'delete 1 2\n' >"$T/bad.txt"
"$TD" ridgemodel "$T/r.geojson" -o "$T/x.tif" --size 200x200 --edits "$T/bad.txt" 2>"$T/err"
check "a bad edit line: one error naming the file and line, exit 1" \
  "[ $? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'bad.txt:1' '$T/err' && [ ! -e '$T/x.tif' ]"
printf '{"type":"FeatureCollection","features":[{"type":' >"$T/trunc.geojson"
"$TD" ridgemodel "$T/trunc.geojson" -o "$T/x.tif" --size 50x50 2>"$T/err"
check "a truncated file: one error naming it, exit 1" \
  "[ $? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'trunc.geojson' '$T/err'"
"$TD" ridgemodel "$T/r.geojson" -o "$T/x.tif" --size 50x50 --slope 90 2>"$T/err"
check "slope 90: refused" "[ $? = 1 ] && grep -q 'slope' '$T/err'"

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
