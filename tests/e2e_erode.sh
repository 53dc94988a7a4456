#!/bin/sh
# End-to-end checks of `topodig generate mound` and `topodig erode`: the
# paper's experiment from the command line, snapshots, field rasters, mass
# log, same bytes for any thread count, bad input (one line, exit 1, no
# output left).  Covers src/pipeline/erode.c (the run with its files).
BUILD=${BUILD:-build}
TD="$BUILD/topodig"
T=$(mktemp -d "${TMPDIR:-/tmp}/tderode.XXXXXX")
trap 'rm -rf "$T"' EXIT
pass=0; fail=0
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; }
check() { if eval "$2"; then ok "$1"; else bad "$1"; fi; }

check "erode --help lists --kq" "$TD erode --help | grep -q -- '--kq'"
check "generate --help lists --noise" "$TD generate --help | grep -q -- '--noise'"
"$TD" generate mound -o "$T/m.tif" --size 64 --noise 0.02 --seed 3 -q
"$TD" generate mound -o "$T/m2.tif" --size 64 --noise 0.02 --seed 3 -q
check "generate: same seed, same bytes" "cmp -s '$T/m.tif' '$T/m2.tif'"
"$TD" erode "$T/m.tif" -o "$T/e.tif" --steps 10 --snapshots 5 --threads 1 \
  --out-water "$T/w.tif" --out-energy "$T/en.tif" --out-sediment "$T/s.tif" \
  --mass-log "$T/mass.csv" 2>"$T/err"
check "erode: exit 0, summary line" "grep -Eq '^erode: 10 steps, eroded [0-9.e+-]+, deposited' '$T/err'"
for f in e e_step0005 e_step0010 w en s; do
  check "$f.tif written" "[ -s '$T/$f.tif' ]"
done
check "mass log: header + 10 steps" "[ \$(wc -l <'$T/mass.csv') = 11 ]"
"$TD" erode "$T/m.tif" -o "$T/e2.tif" --steps 10 --threads 2 -q
check "2 threads: same bytes as 1" "cmp -s '$T/e.tif' '$T/e2.tif'"
if command -v gdalinfo >/dev/null 2>&1; then
  check "gdalinfo opens the eroded DEM" "gdalinfo '$T/e.tif' 2>/dev/null | grep -q 'Size is 64, 64'"
fi
printf 'ncols 4\nnrows 3\nxllcorner 1000\nyllcorner 2000\ncellsize 10\nNODATA_value -9999\n1 2 3 4\n2 3 4 5\n3 4 5 9\n' >"$T/c10.asc"
"$TD" erode "$T/c10.asc" -o "$T/c10o.asc" --steps 2 2>"$T/err"
check "cell size read from the grid's georeferencing" "grep -q 'cell size 10 from the georeferencing' '$T/err'"
check "a georeferenced DEM: the model in cell units, the level deposition, the rest rule" "grep -q 'runs in cell units (heights / 10' '$T/err' && grep -q 'deposit level on a georeferenced DEM' '$T/err' && grep -q 'rest-accel 0.001 on a georeferenced DEM' '$T/err'"
"$TD" erode "$T/c10.asc" -o "$T/c10o.asc" --steps 2 --cell-size 2 2>"$T/err"
check "--cell-size overrides the georeferencing" "! grep -q 'from the georeferencing' '$T/err'"
# cell units: the same as eroding the heights / 10 with cell 1, times 10
# (a 24 x 16 slope with a bump, cell 10, heights in metres)
awk -v c=10 -v d=1 'BEGIN { printf "ncols 24\nnrows 16\nxllcorner 1000\nyllcorner 2000\ncellsize %s\nNODATA_value -9999\n", c;
  for (y = 0; y < 16; y++) { for (x = 0; x < 24; x++) printf "%.6f ", (3 * x + 2 * y + 40 * exp(-((x - 12)^2 + (y - 8)^2) / 20)) / d; printf "\n" } }' >"$T/s10.asc"
awk -v c=1 -v d=10 'BEGIN { printf "ncols 24\nnrows 16\nxllcorner 1000\nyllcorner 2000\ncellsize %s\nNODATA_value -9999\n", c;
  for (y = 0; y < 16; y++) { for (x = 0; x < 24; x++) printf "%.6f ", (3 * x + 2 * y + 40 * exp(-((x - 12)^2 + (y - 8)^2) / 20)) / d; printf "\n" } }' >"$T/s1.asc"
"$TD" erode "$T/s10.asc" -o "$T/s10o.asc" --steps 3 -q
"$TD" erode "$T/s1.asc" -o "$T/s1o.asc" --steps 3 -q
"$TD" erode "$T/s10.asc" -o "$T/s10m.asc" --steps 3 --units map --deposit level -q
check "--units cells: the heights / cell eroded with cell 1, times the cell (within 1e-4)" \
    "paste '$T/s10o.asc' '$T/s1o.asc' | awk 'NR > 6 { n = NF / 2; for (i = 1; i <= n; i++) { d = \$i - 10 * \$(i + n); if (d < 0) d = -d; if (d > m) m = d } } END { exit !(NR == 22 && m < 1e-4 * 200) }'"
check "--units map: another result (the DEM's units)" "! cmp -s '$T/s10o.asc' '$T/s10m.asc' && [ -s '$T/s10m.asc' ]"
if command -v gdal_translate >/dev/null 2>&1; then
  gdal_translate -q -a_srs EPSG:4326 -a_ullr 10 50 10.004 49.997 "$T/c10.asc" "$T/geo.tif" 2>/dev/null
  "$TD" erode "$T/geo.tif" -o "$T/geoo.tif" --steps 1 2>"$T/err"
  check "degrees converted to metres" "grep -Eq 'cell size (8[5-9]|9[0-9])[.0-9]* from the georeferencing \(degrees' '$T/err'"
fi
"$TD" erode "$T/m.tif" -o "$T/lit.tif" --steps 3 --sediment-route paper --flow-speed vector -q
check "paper's literal reading runs" "[ -s '$T/lit.tif' ]"
"$TD" erode "$T/m.tif" -o "$T/lv1.tif" --steps 3 --deposit level --threads 1 -q
"$TD" erode "$T/m.tif" -o "$T/lv2.tif" --steps 3 --deposit level --threads 2 -q
check "--deposit level: same bytes for 1 and 2 threads" "cmp -s '$T/lv1.tif' '$T/lv2.tif'"
check "no temporary files left" "! ls '$T' | grep -q '\.tmp\.'"

expect_fail() { # name, args...
  name=$1; shift
  rm -f "$T/out.tif"
  "$TD" erode "$@" 2>"$T/err"
  rc=$?
  if [ $rc = 1 ] && [ "$(wc -l <"$T/err")" = 1 ] && [ ! -e "$T/out.tif" ]; then
    ok "$name"; else bad "$name (exit $rc: $(cat "$T/err"))"; fi
}
printf 'not a dem' >"$T/junk.tif"
expect_fail "missing file" "$T/nope.tif" -o "$T/out.tif"
expect_fail "junk file" "$T/junk.tif" -o "$T/out.tif"
expect_fail "bad --alpha" "$T/m.tif" -o "$T/out.tif" --alpha 2
expect_fail "bad --steps" "$T/m.tif" -o "$T/out.tif" --steps x
expect_fail "no output" "$T/m.tif"
expect_fail "bad --edges" "$T/m.tif" -o "$T/out.tif" --edges maybe
expect_fail "bad --deposit" "$T/m.tif" -o "$T/out.tif" --deposit lots
expect_fail "bad --sediment-route" "$T/m.tif" -o "$T/out.tif" --sediment-route up
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
