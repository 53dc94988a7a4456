# util/e2e.sh: helpers the end-to-end scripts share (sourced, not run).

# heights_on_dem LINES DEM: the first vertex of up to 12 lines of LINES (any
# format ogrinfo reads) that have a height, looked up on DEM through its
# geotransform; prints "HIT N": how many of the N give the line's height.
heights_on_dem() {
    ogrinfo -ro -al "$1" 2>/dev/null | awk '
        /^  height \([A-Za-z0-9]*\) = / { h = $NF }
        /LINESTRING (Z )?\(/ { sub(/.*LINESTRING (Z )?\(/, ""); split($0, a, /[ ,]/)
                               if (h != "(null)") print h, a[1], a[2] }' |
        head -n 12 | {
        n=0; hit=0
        while read -r hh xx yy; do
            v=$(gdallocationinfo -valonly -geoloc "$2" "$xx" "$yy" 2>/dev/null)
            n=$((n + 1))
            awk -v a="$v" -v b="$hh" 'BEGIN { d = a - b; exit !(a != "" && d * d < 1e-6) }' && hit=$((hit + 1))
        done
        echo "$hit $n"
    }
}

# near A B TOL: |A - B| <= TOL (A empty: no).
near() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; exit !(a != "" && d * d <= t * t) }'; }

# at DEM COL ROW: the DEM's value at a cell (gdallocationinfo).
at() { gdallocationinfo -valonly "$1" "$2" "$3" 2>/dev/null; }

# The pass/fail counters and check NAME CONDITION (eval'd); a script ends
# with e2e_summary.
pass=0; fail=0
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; }
check() { if eval "$2"; then ok "$1"; else bad "$1"; fi; }
e2e_summary() { echo "$pass passed, $fail failed"; [ "$fail" = 0 ]; }
