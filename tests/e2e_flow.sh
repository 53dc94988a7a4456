#!/bin/sh
# End-to-end checks of `topodig flow`: every method from the command line,
# the class raster, --log, gdalinfo reading the outputs, bad input (one
# line, exit 1, nothing written).
BUILD=${BUILD:-build}
TD="$BUILD/topodig"
T=$(mktemp -d "${TMPDIR:-/tmp}/tdflow.XXXXXX")
trap 'rm -rf "$T"' EXIT
pass=0; fail=0
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; }
check() { if eval "$2"; then ok "$1"; else bad "$1"; fi; }

check "flow --help lists --method" "$TD flow --help | grep -q -- '--method'"
check "flow --help lists --ridge-q" "$TD flow --help | grep -q -- '--ridge-q'"
"$TD" generate mound -o "$T/m.tif" --size 80 --noise 0.02 --seed 3 -q
for m in sobel d8 dinf; do
  "$TD" flow "$T/m.tif" -o "$T/p_$m.tif" --method $m --classes "$T/c_$m.tif" 2>"$T/err"
  check "$m: exit 0, summary" "grep -q '^flow: method $m, 6400 cells' '$T/err'"
  check "$m: passes and classes written" "[ -s '$T/p_$m.tif' ] && [ -s '$T/c_$m.tif' ]"
done
check "d8: all rain leaves the grid" "grep -q 'outflow 6400 (100.000%)' '$T/err'"
"$TD" flow "$T/m.tif" -o "$T/q.tif" --method d8 -q 2>"$T/err"
check "--quiet prints nothing" "[ ! -s '$T/err' ]"
"$TD" flow "$T/m.tif" -o "$T/l.tif" --method d8 --log -q
"$TD" generate mound -o "$T/big.tif" --size 600 --noise 0.5 --seed 5 -q
"$TD" flow "$T/big.tif" -o "$T/t1.tif" --method d8 --threads 1 -q
"$TD" flow "$T/big.tif" -o "$T/t2.tif" --method d8 --threads 2 -q
check "d8: same bytes on 1 and 2 threads (600x600, 3x3 tiles)" "cmp -s '$T/t1.tif' '$T/t2.tif'"
if command -v gdalinfo >/dev/null 2>&1; then
  check "gdalinfo: passes float32 80x80" "gdalinfo '$T/p_d8.tif' 2>/dev/null | grep -q 'Size is 80, 80' && gdalinfo '$T/p_d8.tif' | grep -q 'Type=Float32'"
  check "gdalinfo: classes Byte" "gdalinfo '$T/c_d8.tif' 2>/dev/null | grep -q 'Type=Byte'"
  mx=$(gdalinfo -mm "$T/c_d8.tif" 2>/dev/null | sed -n 's/.*Computed Min\/Max=\([0-9.]*\),\([0-9.]*\).*/\1 \2/p')
  check "classes span 1..3 (no nodata in this DEM)" "[ '$mx' = '1.000 3.000' ]"
  lmax=$(gdalinfo -mm "$T/l.tif" 2>/dev/null | sed -n 's/.*Computed Min\/Max=\([-0-9.]*\),\([-0-9.e+]*\).*/\2/p')
  check "--log: max <= log10(6400)" "awk 'BEGIN{exit !($lmax > 0 && $lmax <= 3.8062)}'"
fi
check "no temporary files left" "! ls '$T' | grep -q '\.tmp\.'"

expect_fail() { # name, args...
  name=$1; shift
  rm -f "$T/out.tif" "$T/cls.tif"
  "$TD" flow "$@" 2>"$T/err"
  rc=$?
  if [ $rc = 1 ] && [ "$(wc -l <"$T/err")" = 1 ] && [ ! -e "$T/out.tif" ] && [ ! -e "$T/cls.tif" ]; then
    ok "$name"; else bad "$name (exit $rc: $(cat "$T/err"))"; fi
}
printf 'not a dem' >"$T/junk.tif"
expect_fail "missing file" "$T/nope.tif" -o "$T/out.tif"
expect_fail "junk file" "$T/junk.tif" -o "$T/out.tif"
expect_fail "bad --method" "$T/m.tif" -o "$T/out.tif" --method d16
expect_fail "bad --ridge-q" "$T/m.tif" -o "$T/out.tif" --ridge-q 1.5
expect_fail "ridge-q above valley-q" "$T/m.tif" -o "$T/out.tif" --ridge-q 0.9 --valley-q 0.5 --classes "$T/cls.tif"
expect_fail "bad --max-steps" "$T/m.tif" -o "$T/out.tif" --max-steps -3
expect_fail "bad --threads" "$T/m.tif" -o "$T/out.tif" --method d8 --threads -1
expect_fail "no output" "$T/m.tif"
expect_fail "two inputs" "$T/m.tif" "$T/m.tif" -o "$T/out.tif"
expect_fail "classes into a missing folder" "$T/m.tif" -o "$T/out.tif" --classes "$T/no/such/dir/c.tif"
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
