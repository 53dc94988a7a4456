#!/bin/sh
# Run the source checks (tests/check_*.sh: the include layers), every
# test binary (build/tests/test_*), every end-to-end script
# (tests/e2e_*.sh) and the binaries named in EXTRA_TESTS; each prints
# "N passed, N failed"
# as its last line.  Prints the totals the same way, once, and exits 1
# when anything failed.
BUILD=${BUILD:-build}
pass=0; fail=0; broken=""
for t in tests/check_*.sh "$BUILD"/tests/test_* tests/e2e_*.sh ${EXTRA_TESTS:-}; do
    [ -e "$t" ] || continue
    case "$t" in *.o|*.d) continue ;; esac
    echo "== $t"
    out=$( (if [ "${t%.sh}" != "$t" ]; then BUILD="$BUILD" sh "$t"; else "$t"; fi) 2>&1 )
    rc=$?
    printf '%s\n' "$out" | grep -v '^ok ' | grep -v '^[0-9]* passed, [0-9]* failed$'
    line=$(printf '%s\n' "$out" | grep -E '^[0-9]+ passed, [0-9]+ failed$' | tail -n 1)
    if [ -z "$line" ]; then
        echo "   $t crashed or printed no summary (exit $rc)"
        fail=$((fail + 1)); broken="$broken $t"; continue
    fi
    p=${line%% passed*}; f=${line#*passed, }; f=${f%% failed*}
    echo "   $line"
    pass=$((pass + p)); fail=$((fail + f))
    if [ "$f" = 0 ] && [ "$rc" != 0 ]; then
        echo "   $t exited $rc"; fail=$((fail + 1)); broken="$broken $t"
    fi
done
[ -n "$broken" ] && echo "broken:$broken"
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
