#!/bin/sh
# End-to-end checks of `topodig insolation`: both methods from the command
# line, --horizons (k bands) and --skyview, gdalinfo reading the outputs,
# a flat plane's analytic value, bad input (one line, exit 1, nothing
# written).
BUILD=${BUILD:-build}
TD="$BUILD/topodig"
T=$(mktemp -d "${TMPDIR:-/tmp}/tdsun.XXXXXX")
trap 'rm -rf "$T"' EXIT
pass=0; fail=0
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; }
check() { if eval "$2"; then ok "$1"; else bad "$1"; fi; }

check "insolation --help lists --method" "$TD insolation --help | grep -q -- 'hidden-surface'"
check "insolation --help states the sky-view definition" "$TD insolation --help | grep -q 'radiative'"
check "insolation --help states the unit" "$TD insolation --help | grep -q 'Wh/m^2'"
"$TD" generate mound -o "$T/m.tif" --size 64 --noise 0.02 --seed 3 -q
"$TD" insolation "$T/m.tif" -o "$T/s.tif" --lat 39.5 --day 172 --directions 16 \
  --horizons "$T/h.tif" --skyview "$T/v.tif" 2>"$T/err"
check "horizon: exit 0, summary" "grep -q '^insolation: method horizon, 16 directions, 4096 cells' '$T/err'"
check "horizon: all three written" "[ -s '$T/s.tif' ] && [ -s '$T/h.tif' ] && [ -s '$T/v.tif' ]"
"$TD" insolation "$T/m.tif" -o "$T/z.tif" --lat 39.5 --day 172 --method hidden-surface \
  --viewpoints 64 --skyview "$T/zv.tif" 2>"$T/err"
check "hidden-surface: exit 0, summary" "grep -q '^insolation: method hidden-surface, 64 viewpoints (16 azimuths x 4 rings)' '$T/err'"
"$TD" insolation "$T/m.tif" -o "$T/q.tif" --lat 39.5 --day 172 -q 2>"$T/err"
check "--quiet prints nothing" "[ ! -s '$T/err' ]"
"$TD" generate mound -o "$T/flat.tif" --size 20 --relief 0 --noise 0 -q
"$TD" insolation "$T/flat.tif" -o "$T/f.tif" --lat 40 --day 172 --step-minutes 5 2>"$T/err"
# the clear-sky day on flat ground at 40N, day 172 (tests/test_insolation.c: 8314 Wh/m^2)
check "flat plane: mean 8314 +- 0.5%" "grep -q 'mean daily total 8[23][0-9][0-9]\.' '$T/err' && awk -v v=\$(sed -n 's/.*mean daily total \([0-9.]*\).*/\1/p' '$T/err') 'BEGIN{exit !(v > 8272 && v < 8356)}'"
if command -v gdalinfo >/dev/null 2>&1; then
  check "gdalinfo: total float32 64x64 with nodata" "gdalinfo '$T/s.tif' 2>/dev/null | grep -q 'Size is 64, 64' && gdalinfo '$T/s.tif' | grep -q 'Type=Float32' && gdalinfo '$T/s.tif' | grep -q 'NoData Value'"
  check "gdalinfo: horizons have 16 bands" "[ \$(gdalinfo '$T/h.tif' 2>/dev/null | grep -c '^Band ') = 16 ]"
  mx=$(gdalinfo -mm "$T/v.tif" 2>/dev/null | sed -n 's/.*Computed Min\/Max=\([0-9.]*\),\([0-9.]*\).*/\2/p')
  check "sky view at most 1" "awk 'BEGIN{exit !($mx <= 1.0 && $mx > 0.9)}'"
  fmm=$(gdalinfo -mm "$T/v.tif" 2>/dev/null | grep -c 'Min/Max')
  check "gdalinfo reads the sky view" "[ '$fmm' = 1 ]"
fi
check "insolation --help lists --earth-curvature" "$TD insolation --help | grep -q -- '--earth-curvature'"
# 2 km cells: horizons tens of km away sink by d^2 / 2R (about 80 m at 32 km)
"$TD" insolation "$T/m.tif" -o "$T/c0.tif" --lat 40 --day 172 --directions 8 --cell-size 2000 --horizons "$T/h0.tif" -q
"$TD" insolation "$T/m.tif" -o "$T/c1.tif" --lat 40 --day 172 --directions 8 --cell-size 2000 --horizons "$T/h1.tif" --earth-curvature -q
check "--earth-curvature: exit 0, horizons change" "[ -s '$T/h1.tif' ] && ! cmp -s '$T/h0.tif' '$T/h1.tif'"
if command -v gdalinfo >/dev/null 2>&1; then
  m0=$(gdalinfo -stats "$T/h0.tif" 2>/dev/null | sed -n 's/.*STATISTICS_MEAN=//p' | head -n 1)
  m1=$(gdalinfo -stats "$T/h1.tif" 2>/dev/null | sed -n 's/.*STATISTICS_MEAN=//p' | head -n 1)
  check "--earth-curvature lowers the horizons ($m1 < $m0)" "awk 'BEGIN{exit !($m1 < $m0)}'"
  rm -f "$T"/*.aux.xml
fi
check "no temporary files left" "! ls '$T' | grep -q '\.tmp\.'"

expect_fail() { # name, args...
  name=$1; shift
  rm -f "$T/out.tif" "$T/hz.tif" "$T/sv.tif"
  "$TD" insolation "$@" 2>"$T/err"
  rc=$?
  if [ $rc = 1 ] && [ "$(wc -l <"$T/err")" = 1 ] && [ ! -e "$T/out.tif" ] && [ ! -e "$T/hz.tif" ] && [ ! -e "$T/sv.tif" ]; then
    ok "$name"; else bad "$name (exit $rc: $(cat "$T/err"))"; fi
}
printf 'not a dem' >"$T/junk.tif"
expect_fail "missing --lat" "$T/m.tif" -o "$T/out.tif" --day 172
expect_fail "missing --day" "$T/m.tif" -o "$T/out.tif" --lat 40
expect_fail "latitude out of range" "$T/m.tif" -o "$T/out.tif" --lat 91 --day 172
expect_fail "latitude not a number" "$T/m.tif" -o "$T/out.tif" --lat north --day 172
expect_fail "day 0" "$T/m.tif" -o "$T/out.tif" --lat 40 --day 0
expect_fail "day 367" "$T/m.tif" -o "$T/out.tif" --lat 40 --day 367
expect_fail "missing file" "$T/nope.tif" -o "$T/out.tif" --lat 40 --day 172
expect_fail "junk DEM" "$T/junk.tif" -o "$T/out.tif" --lat 40 --day 172
expect_fail "bad --method" "$T/m.tif" -o "$T/out.tif" --lat 40 --day 172 --method rays
expect_fail "bad --directions" "$T/m.tif" -o "$T/out.tif" --lat 40 --day 172 --directions 0
expect_fail "bad --viewpoints" "$T/m.tif" -o "$T/out.tif" --lat 40 --day 172 --method hidden-surface --viewpoints 2
expect_fail "bad --step-minutes" "$T/m.tif" -o "$T/out.tif" --lat 40 --day 172 --step-minutes 0
expect_fail "bad --cell-size" "$T/m.tif" -o "$T/out.tif" --lat 40 --day 172 --cell-size -1
expect_fail "no output" "$T/m.tif" --lat 40 --day 172
expect_fail "--earth-curvature with hidden-surface" "$T/m.tif" -o "$T/out.tif" --lat 40 --day 172 --method hidden-surface --viewpoints 16 --earth-curvature
expect_fail "horizons into a missing folder" "$T/m.tif" -o "$T/out.tif" --lat 40 --day 172 --horizons "$T/no/such/h.tif"
expect_fail "sky view into a missing folder" "$T/m.tif" -o "$T/out.tif" --lat 40 --day 172 --horizons "$T/hz.tif" --skyview "$T/no/such/v.tif"
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
