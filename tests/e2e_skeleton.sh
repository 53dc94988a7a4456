#!/bin/sh
# End-to-end checks of topodig skeleton (src/cli/skeleton.c; the straight
# skeleton of a key outline, paper 004): a rectangle's hip roof read back
# from the DEM at known cells, contours every interval with their heights,
# --height scaling the summit, the strata, a Polygon with a reflex corner
# (a split event) by both constructions, and bad input (one error line, exit 1, no output written).
BUILD=${BUILD:-build}
TD="$BUILD/topodig"
T=$(mktemp -d "${TMPDIR:-/tmp}/tdsk.XXXXXX")
trap 'rm -rf "$T"' EXIT
pass=0; fail=0
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; }
check() { if eval "$2"; then ok "$1"; else bad "$1"; fi; }
. tests/util/e2e.sh # near, at

check "skeleton --help" "$TD skeleton --help | grep -q '^usage: topodig skeleton'"

# --- a rectangle 80 x 40 as a closed LineString, slope 45: the hip roof
cat >"$T/r.geojson" <<'EOT'
{"type":"FeatureCollection","features":[
{"type":"Feature","properties":{},"geometry":{"type":"LineString","coordinates":[[10,-10],[90,-10],[90,-50],[10,-50],[10,-10]]}}]}
EOT
"$TD" skeleton "$T/r.geojson" -o "$T/r.tif" --size 100x60 --slope 45 --interval 5 --base 100 --contours-out "$T/c.geojson" --surface roof 2>"$T/err"
rc=$?
check "rectangle: exit 0, one summary line, summit 120, 3 contours" \
  "[ $rc = 0 ] && [ \$(grep -vc '^[a-z][a-z +]*: [0-9]*%\$' '$T/err') = 1 ] && grep -q '^skeleton: 4 corners, .*summit 120, 3 contours, 0 strata rings, 3200 cells' '$T/err'"
if command -v gdallocationinfo >/dev/null 2>&1; then
  check "hip roof: 5.5 cells in from the top edge, 105.5" "near '$(at "$T/r.tif" 50 15)' 105.5 0.001"
  check "hip roof: on the ridge, 119.5" "near '$(at "$T/r.tif" 50 29)' 119.5 0.001"
  check "hip roof: outside the outline, nodata" "[ \"\$(at '$T/r.tif' 5 5)\" = '-9999' ]"
fi
check "contours at 105, 110, 115" \
  "grep -q '\"height\": *105' '$T/c.geojson' && grep -q '\"height\": *110' '$T/c.geojson' && grep -q '\"height\": *115' '$T/c.geojson'"

# --- strata: 3 layers of the rectangle's 20 (summit 120): rings at 105, 110, 115
"$TD" skeleton "$T/r.geojson" -o "$T/r2.tif" --size 100x60 --slope 45 --interval 10 --base 100 --strata 3 --strata-out "$T/s.geojson" 2>"$T/err"
check "--strata 3: three rings at 105, 110, 115" \
  "[ \$? = 0 ] && grep -q '3 strata rings' '$T/err' && grep -q '\"height\": *105' '$T/s.geojson' && grep -q '\"height\": *110' '$T/s.geojson' && grep -q '\"height\": *115' '$T/s.geojson'"
"$TD" skeleton "$T/r.geojson" -o "$T/x.tif" --size 100x60 --slope 45 --interval 10 --strata 3 2>"$T/err"
check "--strata without --strata-out: one error line, exit 1" "[ \$? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && [ ! -e '$T/x.tif' ]"

# --- a Polygon with a reflex corner, scaled to a summit of 300
cat >"$T/p.geojson" <<'EOT'
{"type":"FeatureCollection","features":[
{"type":"Feature","properties":{},"geometry":{"type":"Polygon","coordinates":[[[20,-20],[180,-30],[200,-120],[140,-110],[120,-180],[40,-170],[60,-100],[20,-20]]]}}]}
EOT
"$TD" skeleton "$T/p.geojson" -o "$T/p.tif" --size 220x200 --height 300 --interval 20 2>"$T/err"
rc=$?
check "a reflex corner: exit 0, a split event, summit 300" \
  "[ $rc = 0 ] && grep -Eq 'events \([1-9][0-9]* splits\), summit 300,' '$T/err'"
"$TD" skeleton "$T/p.geojson" -o "$T/pr.tif" --size 220x200 --height 300 --interval 20 --surface roof -q
"$TD" compare "$T/p.tif" "$T/pr.tif" --json >"$T/pc.json"
check "the paper's TIN (default) near the roof, below it on the whole" \
  "awk -F'[:,]' '{ for (i = 1; i < NF; i++) { if (\$i ~ /\"rmse\"/) r = \$(i+1); if (\$i ~ /\"bias\"/) b = \$(i+1) } } END { exit !(r > 0 && r < 45 && b < 0) }' '$T/pc.json'"

# --- the paper's construction gives the same roof as the queue (default)
"$TD" skeleton "$T/p.geojson" -o "$T/pp.tif" --size 220x200 --height 300 --interval 20 --surface roof --construction paper -q
"$TD" compare "$T/pr.tif" "$T/pp.tif" --json >"$T/pq.json"
check "--construction paper: the queue's roof (largest difference < 0.01)" \
  "awk -F'[:,]' '{ for (i = 1; i < NF; i++) if (\$i ~ /\"max_abs\"/) m = \$(i+1) } END { exit !(m != \"\" && m + 0 < 0.01) }' '$T/pq.json'"

# --- bad input
cat >"$T/bow.geojson" <<'EOT'
{"type":"FeatureCollection","features":[
{"type":"Feature","properties":{},"geometry":{"type":"Polygon","coordinates":[[[10,-10],[50,-50],[50,-10],[10,-50],[10,-10]]]}}]}
EOT
"$TD" skeleton "$T/bow.geojson" -o "$T/x.tif" --size 60x60 --slope 30 --interval 5 2>"$T/err"
check "an outline crossing itself: one error line, exit 1, no output" \
  "[ $? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'crosses or touches itself' '$T/err' && [ ! -e '$T/x.tif' ]"
"$TD" skeleton "$T/r.geojson" -o "$T/x.tif" --size 60x60 --interval 5 2>"$T/err"
check "neither --height nor --slope: one error line, exit 1" "[ $? = 1 ] && [ \$(wc -l <'$T/err') = 1 ]"
cat >"$T/open.geojson" <<'EOT'
{"type":"FeatureCollection","features":[
{"type":"Feature","properties":{},"geometry":{"type":"LineString","coordinates":[[10,-10],[50,-10],[50,-50]]}}]}
EOT
"$TD" skeleton "$T/open.geojson" -o "$T/x.tif" --size 60x60 --slope 30 --interval 5 2>"$T/err"
check "no closed outline: one error naming the file, exit 1" \
  "[ $? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'open.geojson.*no Polygon' '$T/err'"

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
