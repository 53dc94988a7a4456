#!/bin/sh
# End-to-end checks of `topodig label`: help, bad input (one error line,
# exit 1, no output), and, once the GeoJSON reader is in the library, a run
# on the scanned sample with two known points, the summary line, the CSV
# round trip and a contradictory pair of points.  Covers src/cli/label.c,
# label_entry.c (--interactive), label_report.c, src/pipeline/label.c and
# the CSV files (src/io/csv.c).
BUILD=${BUILD:-build}
TD="$BUILD/topodig"
T=$(mktemp -d "${TMPDIR:-/tmp}/tdlabel.XXXXXX")
trap 'rm -rf "$T"' EXIT
pass=0; fail=0
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; }
check() { if eval "$2"; then ok "$1"; else bad "$1"; fi; }
one_error() { [ "$(wc -l <"$T/err")" = 1 ] && grep -q "^topodig label: $1" "$T/err"; }

check "label --help lists --known" "$TD label --help | grep -q -- '--known'"
"$TD" label x.geojson -o "$T/o.geojson" 2>"$T/err"
check "no --interval: exit 1, one line" "[ $? = 1 ] && one_error 'no interval'"
"$TD" label x.geojson -o "$T/o.geojson" --interval 10 --known 1,2 2>"$T/err"
check "bad --known: exit 1, one line" "[ $? = 1 ] && one_error '--known'"
"$TD" label x.geojson -o "$T/o.geojson" --interval -5 2>"$T/err"
check "negative interval: exit 1" "[ $? = 1 ] && one_error '--interval'"
check "no output left behind" "[ ! -e '$T/o.geojson' ]"

"$TD" scan samples/hills.png -o "$T/lines.geojson" -q
"$TD" label --labeller tree "$T/lines.geojson" -o "$T/lab.geojson" --interval 20 \
    --known 210.5,260.8,180 --known 267.5,244.2,200 --export-csv "$T/h.csv" \
    2>"$T/err"
rc=$?
if grep -q "no GeoJSON reader" "$T/err"; then
    echo "note: src/geojson_read.c not in the library yet: run checks skipped"
else
    check "label sample: exit 0" "[ $rc = 0 ]"
    check "label sample: summary line" \
      "grep -Eq '^label: [0-9]+ lines, [0-9]+ labelled, 0 undetermined, 0 warnings' '$T/err'"
    check "label sample: heights written" \
      "! grep -q '\"height\":null' '$T/lab.geojson'"
    "$TD" label --labeller tree "$T/lines.geojson" -o "$T/lab2.geojson" --interval 20 \
        --heights "$T/h.csv" --export-csv "$T/h2.csv" -q
    check "CSV round trip gives the same heights" "cmp -s '$T/h.csv' '$T/h2.csv'"
    "$TD" label --labeller tree "$T/lines.geojson" -o "$T/bad.geojson" --interval 20 \
        --known 210.5,260.8,180 --known 267.5,244.2,300 2>"$T/err"
    check "contradictory points: exit 1 naming both" \
      "[ $? = 1 ] && one_error 'known points contradict' && grep -q '(210.5,260.8)=180' '$T/err' && grep -q '(267.5,244.2)=300' '$T/err'"
    check "no output on error" "[ ! -e '$T/bad.geojson' ]"

    # --interactive with piped answers: Enter x3, 180, 200, then end of
    # input (accept the rest): the same heights as the two known points.
    printf '\n\n\n180\n200\n' | "$TD" label --labeller tree "$T/lines.geojson" -o "$T/int.geojson" \
        --interval 20 --interactive --like samples/hills.png \
        --export-csv "$T/int.csv" 2>"$T/err"
    check "interactive: exit 0" "[ $? = 0 ]"
    check "interactive: label sheet written first" \
      "[ -s '$T/int.geojson.png' ] && head -1 '$T/err' | grep -q 'label sheet'"
    check "interactive: one prompt per answer, then end of input" \
      "[ \$(grep -c 'height \\[' '$T/err') = 6 ]"
    check "interactive: typed heights re-suggest the rest" \
      "grep -q '^line 4 .*height \\[200\\]: 200' '$T/err'"
    check "interactive: same heights as two known points" \
      "cmp -s '$T/h.csv' '$T/int.csv'"
    printf 'abc\n\nq\n' | "$TD" label --labeller tree "$T/lines.geojson" -o "$T/q.geojson" \
        --interval 20 --interactive --label-sheet "$T/q.png" 2>"$T/err"
    check "interactive: q stops, bad answer asked again" \
      "[ $? = 0 ] && [ \$(grep -c 'height \\[' '$T/err') = 3 ] && grep -q 'Enter to accept' '$T/err' && [ -s '$T/q.png' ]"
    printf '185\n' | "$TD" label --labeller tree "$T/lines.geojson" -o "$T/w.geojson" \
        --interval 20 --interactive --label-sheet "$T/w.png" 2>"$T/err"
    check "interactive: off-interval height warned" \
      "grep -q 'warning: height 185 for line 0' '$T/err'"

    cat >"$T/x.geojson" <<'JSON'
{"type":"FeatureCollection","features":[
{"type":"Feature","properties":{"id":7},"geometry":{"type":"LineString","coordinates":[[0.5,50.5],[99.5,50.5]]}},
{"type":"Feature","properties":{"id":9},"geometry":{"type":"LineString","coordinates":[[40.5,0.5],[60.5,99.5]]}}]}
JSON
    "$TD" label --labeller tree "$T/x.geojson" -o "$T/x.out.geojson" --interval 10 \
        --size 100x100 2>"$T/err"
    check "crossing lines: warning naming both and the place" \
      "[ $? = 0 ] && grep -q 'warning: lines 7 and 9 cross at (50.6,50.5)' '$T/err' && grep -q ', 1 warnings' '$T/err'"

    # Undetermined lines export as "id," and read back as no height.
    "$TD" label --labeller tree "$T/lines.geojson" -o "$T/u.geojson" --interval 20 \
        --export-csv "$T/u.csv" -q
    "$TD" label --labeller tree "$T/lines.geojson" -o "$T/u2.geojson" --interval 20 \
        --heights "$T/u.csv" --export-csv "$T/u2.csv" 2>"$T/err"
    check "CSV round trip with undetermined lines" \
      "[ $? = 0 ] && grep -q '^0,\$' '$T/u.csv' && cmp -s '$T/u.csv' '$T/u2.csv'"
    sed 's/^3,.*/3,245/' "$T/h.csv" >"$T/h3.csv"
    "$TD" label --labeller tree "$T/lines.geojson" -o "$T/h3.geojson" --interval 20 \
        --heights "$T/h3.csv" 2>"$T/err"
    check "--heights off the interval: warned with the place, counted" \
      "[ $? = 0 ] && grep -q '^label: warning: --heights: height 245 of line 3 (near [0-9]*,[0-9]*)' '$T/err' && grep -q ', 1 warnings' '$T/err'"
    printf '180\n\n\n\n300\n' | "$TD" label --labeller tree "$T/lines.geojson" \
        -o "$T/c.geojson" --interval 20 --interactive --label-sheet "$T/c.png" \
        2>"$T/err"
    check "interactive: contradicting typed heights counted" \
      "grep -q 'heights not re-suggested' '$T/err' && grep -q ', 1 warnings' '$T/err'"
    "$TD" label --labeller tree "$T/lines.geojson" -o "$T/one.geojson" --interval 20 \
        --known 210.5,260.8,180 2>"$T/err"
    check "one known point: the assumed lines listed" \
      "grep -q '^label: note: 25 lines are higher or lower' '$T/err'"
    # the faces labeller with two known points: nearly every height comes
    # from the defaults (rings rise), and the summary says so
    "$TD" label "$T/lines.geojson" -o "$T/two.geojson" --interval 20 \
        --known 210.5,260.8,180 --known 267.5,244.2,200 2>"$T/err"
    check "two known points: a note that most heights are assumed" \
      "[ $? = 0 ] && grep -q '^label: note: 22 of the 24 lines with a height (92 %) took it from the defaults alone' '$T/err'"

    # Index contours drawn thicker: the scan measures widths, label checks.
    "$BUILD/tdgen" -o "$T/cone.png" --terrain cone --size 400x300 \
        --index-width 4 -q
    check "tdgen -q and --index-width" "[ $? = 0 ] && [ -s '$T/cone.png' ]"
    "$TD" scan "$T/cone.png" -o "$T/cone.geojson" -q
    check "scan writes line widths" "grep -q '\"width\":4' '$T/cone.geojson'"
    # rings only (the corner lines need a point per corner)
    "$TD" label --labeller tree "$T/cone.geojson" -o "$T/cl.geojson" --interval 20 \
        --known 200,150,398 --index-every 5 2>"$T/err"
    check "index check: right heights, at most the 3 corner lines flagged" \
      "[ $? = 0 ] && [ \$(grep -c 'drawn' '$T/err') -le 3 ] && ! grep -q 'look' '$T/err'"
    "$TD" label --labeller tree "$T/cone.geojson" -o "$T/cl.geojson" --interval 20 \
        --known 200,150,418 --index-every 5 2>"$T/err"
    check "index check: heights one interval high named" \
      "[ $? = 0 ] && [ \$(grep -c 'is drawn thick' '$T/err') -ge 5 ] && grep -q 'heights look +20 off' '$T/err'"
    sed 's/,"width":[0-9.]*//' "$T/cone.geojson" >"$T/nw.geojson"
    "$TD" label --labeller tree "$T/nw.geojson" -o "$T/cl.geojson" --interval 20 \
        --known 200,150,418 --index-every 5 --like "$T/cone.png" 2>"$T/err"
    check "index check: widths measured on --like SCAN" \
      "grep -q 'heights look +20 off' '$T/err'"

    # Inline labels on curved stretches: joined along the curves by default.
    "$BUILD/tdgen" -o "$T/lab.png" --size 1000x800 --width 2.5 --labels 3 \
        --label-bend 15 -q
    "$BUILD/tdgen" -o "$T/nolab.png" --size 1000x800 --width 2.5 -q
    check "tdgen --labels draws labels" "! cmp -s '$T/lab.png' '$T/nolab.png'"
    "$TD" scan "$T/lab.png" -o "$T/lab.geojson" 2>"$T/err"
    "$TD" scan "$T/lab.png" -o "$T/lab2.geojson" --no-curves 2>"$T/err2"
    n1=$(sed -n 's/.* \([0-9]*\) lines,.*/\1/p' "$T/err")
    n2=$(sed -n 's/.* \([0-9]*\) lines,.*/\1/p' "$T/err2")
    check "curved label gaps joined (fewer lines than with --no-curves)" \
      "[ -n '$n1' ] && [ -n '$n2' ] && [ $n1 -lt $n2 ]"

    # The faces labeller (the default): heights with their source and
    # confidence, honest about what one known point leaves open.
    "$TD" label "$T/lines.geojson" -o "$T/f.geojson" --interval 20 \
        --known 123.5,263.996,120 --known 267.5,244.206,200 \
        --known 561.5,77.084,240 --depressions 205,336 --size 600x450 \
        --debug-dir "$T/fdbg" --like samples/hills.png 2>"$T/err"
    check "faces: exit 0, heights line counts 3 known" \
      "[ $? = 0 ] && grep -q '^label: heights: 3 known, 0 from labels' '$T/err'"
    check "faces: height_source and confidence written" \
      "grep -q '\"height_source\":\"known\",\"confidence\":1.000' '$T/f.geojson' && grep -q '\"height_source\":\"solved\"' '$T/f.geojson'"
    check "faces: --debug-dir heights.png" \
      "[ \"\$(head -c 4 '$T/fdbg/heights.png' | tail -c 3)\" = PNG ]"
    if command -v ogrinfo >/dev/null; then
        check "faces: ogrinfo reads height_source" \
          "ogrinfo -ro -al -so '$T/f.geojson' | grep -q 'height_source: String'"
    fi
    "$TD" label "$T/lines.geojson" -o "$T/f1.geojson" --interval 20 \
        --known 123.5,263.996,120 --size 600x450 2>"$T/err"
    check "faces, one known point: open lines without height, with a reason" \
      "[ $? = 0 ] && grep -q '\"height\":null.*\"height_reason\":\"undecided' '$T/f1.geojson' && ! grep -q '\"height_source\":\"solved\"' '$T/f1.geojson'"
    "$TD" label "$T/lines.geojson" -o "$T/f2.geojson" --interval 20 \
        --known 123.5,263.996,120 --known 123.5,263.996,160 --size 600x450 \
        2>"$T/err"
    check "faces, contradicting points: exit 0, a warning naming the line" \
      "[ $? = 0 ] && grep -q 'warning: line [0-9]*: two known points disagree (120 and 160)' '$T/err'"
    # --sheet SCAN: the printed labels read, the interval inferred
    "$BUILD/tdgen" --dem-in tests/data/dems/frontrange_srtm3.tif --scale 10 \
        --width 1.8 --index-width 3.2 --labels 3 --label-bend 40 \
        --label-font dejavu --noise 6 -o "$T/fr.png" -q
    "$TD" scan "$T/fr.png" -o "$T/fr.geojson" -q
    "$TD" label "$T/fr.geojson" -o "$T/frl.geojson" --sheet "$T/fr.png" 2>"$T/err"
    check "label --sheet: labels read, interval 50 inferred, heights from labels" \
      "[ $? = 0 ] && grep -q 'interval 50 inferred from [0-9]* printed labels' '$T/err' && grep -q '\"height_source\":\"label\"' '$T/frl.geojson'"
    "$TD" label "$T/fr.geojson" -o "$T/frx.geojson" 2>"$T/err"
    check "label without --interval or --sheet: exit 1 naming both" \
      "[ $? = 1 ] && one_error 'no interval: give --interval I (or --sheet SCAN'"
    "$TD" label "$T/lines.geojson" -o "$T/f3.geojson" --interval 20 \
        --labeller magic 2>"$T/err"
    check "--labeller magic: exit 1, one line" "[ $? = 1 ] && one_error '--labeller'"
    # walls: the crowded sheet's blobs, from scan to label
    "$BUILD/tdgen" --dem-in tests/data/dems/frontrange_srtm3.tif --scale 10 \
        --interval 20 --width 1.8 --index-width 3.2 --blur 0.8 --noise 8 \
        -o "$T/cr.png" -q
    "$TD" scan "$T/cr.png" -o "$T/cr.geojson" --walls "$T/crw.geojson" -q
    check "scan --walls: the blobs written" \
      "[ $? = 0 ] && [ \$(grep -c '\"type\":\"Feature\"' '$T/crw.geojson') -gt 50 ]"
    "$TD" label "$T/cr.geojson" -o "$T/crl0.geojson" --interval 20 \
        --known 1.5,1.5,0 2>"$T/err0"
    "$TD" label "$T/cr.geojson" -o "$T/crl.geojson" --interval 20 \
        --known 1.5,1.5,0 --walls "$T/crw.geojson" 2>"$T/err"
    c0=$(sed -n 's/.* \([0-9]*\) face conflicts.*/\1/p' "$T/err0")
    c1=$(sed -n 's/.* \([0-9]*\) face conflicts.*/\1/p' "$T/err")
    check "label --walls: fewer faces leak ($c0 -> $c1 conflicts)" \
      "[ -n '$c0' ] && [ -n '$c1' ] && [ $c1 -lt $((c0 / 2)) ]"
    "$TD" label "$T/cr.geojson" -o "$T/crl2.geojson" --interval 20 \
        --known 1.5,1.5,0 --walls "$T/nowalls.geojson" 2>"$T/err"
    check "label --walls missing file: exit 1, one line naming it" \
      "[ $? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q nowalls.geojson '$T/err' && [ ! -e '$T/crl2.geojson' ]"
fi
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
