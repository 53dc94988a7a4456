#!/bin/sh
# End-to-end checks of topodig batch and mosaic (src/cli/batch.c,
# src/cli/mosaic.c): a manifest of two labelled sheets drawn from a real DEM
# and a broken one, run two at a time: one JSON line per sheet, the outputs
# in their folders, the broken sheet failing alone, exit 1; --resume skips
# what is done and reruns what changed; the jobs emitted for GNU parallel
# give byte-identical outputs; make and Slurm forms; mosaic puts a DEM cut
# in two back together exactly; bad manifests refused.
BUILD=${BUILD:-build}
TD="$BUILD/topodig"
TDA=$(cd "$(dirname "$TD")" && pwd)/$(basename "$TD")
T=$(mktemp -d "${TMPDIR:-/tmp}/tdbt.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/util/e2e.sh # ok, bad, check, e2e_summary
DEM=tests/data/dems/elkhorn_srtm3.tif
[ -e "$DEM" ] || DEM=../shared/dems/elkhorn_srtm3.tif

check "batch --help" "$TD batch --help | grep -q '^usage: topodig batch'"
for n in 6 8; do
  "$BUILD/tdgen" --dem-in "$DEM" --scale 6 --width 1.8 --index-width 3.2 \
      --labels 3 --label-bend 40 --label-font dejavu --blur 0.6 --noise $n \
      -o "$T/elk$n.png" -q
done
printf 'not an image' >"$T/broken.png"
printf 'sheet,options\nelk6.png,\n# a comment\nelk8.png,--interval 10\nbroken.png,\n' >"$T/m.csv"
"$TD" batch "$T/m.csv" --out "$T/out" --jobs 2 2>"$T/err"
rc=$?
check "batch: exit 1 (one sheet failed), a line per sheet" \
  "[ $rc = 1 ] && [ \$(wc -l <'$T/out/batch.log') = 3 ] && grep -q '3 sheets, 1 failed' '$T/err'"
check "the two good sheets: ok, their DEM, lines, summary" \
  "[ \$(grep -c '\"status\": \"ok\"' '$T/out/batch.log') = 2 ] && [ -s '$T/out/elk6/dem.tif' ] && [ -s '$T/out/elk8/lines.geojson' ] && grep -q '\"summary\": {\"lines\": ' '$T/out/batch.log'"
check "the broken sheet: failed, the error names it" \
  "grep '\"status\": \"failed\"' '$T/out/batch.log' | grep -q 'broken.png: not a PNG'"
"$TD" batch "$T/m.csv" --out "$T/out" --resume 2>/dev/null
check "--resume: the done sheets skipped, the broken one tried again" \
  "[ \$(grep -c '\"status\": \"skipped\"' '$T/out/batch.log') = 2 ] && [ \$(grep -c '\"status\": \"failed\"' '$T/out/batch.log') = 1 ]"
printf 'sheet,options\nelk6.png,\nelk8.png,--interval 10 --method scanline\n' >"$T/m2.csv"
"$TD" batch "$T/m2.csv" --out "$T/out" --resume 2>/dev/null
check "--resume with changed options: that sheet runs again, exit 0" \
  "[ \$? = 0 ] && grep 'elk8' '$T/out/batch.log' | grep -q '\"status\": \"ok\"' && grep 'elk6' '$T/out/batch.log' | grep -q skipped"

(cd "$T" && "$TDA" batch --emit parallel m.csv --out par >jobs.txt)
check "--emit parallel: one job line per sheet" "[ \$(wc -l <'$T/jobs.txt') = 3 ]"
if command -v parallel >/dev/null 2>&1; then
  (cd "$T" && parallel -j 2 <jobs.txt >/dev/null 2>&1)
else
  (cd "$T" && sh jobs.txt >/dev/null 2>&1)
fi
check "the emitted jobs: outputs byte-identical to batch's" \
  "cmp -s '$T/out/elk6/dem.tif' '$T/par/elk6/dem.tif' && cmp -s '$T/out/elk6/lines.geojson' '$T/par/elk6/lines.geojson'"
(cd "$T" && "$TDA" batch --emit make m.csv --out mk >jobs.mk && "$TDA" batch --emit slurm m.csv --out sl >jobs.sh)
check "--emit make: a Makefile make reads" "(cd '$T' && make -n -f jobs.mk >/dev/null 2>&1)"
check "--emit slurm: an array of 3, sh syntax" "grep -q '^#SBATCH --array=1-3' '$T/jobs.sh' && sh -n '$T/jobs.sh'"

# mosaic: the Elkhorn DEM cut in two with an overlap, put back together
gdal_translate -q -srcwin 0 0 200 359 "$DEM" "$T/a.tif" && gdal_translate -q -srcwin 180 0 187 359 "$DEM" "$T/b.tif"
"$TD" mosaic "$T/a.tif" "$T/b.tif" -o "$T/m.tif" -q
check "mosaic .tif: the DEM again (RMSE 0)" "$TD compare '$DEM' '$T/m.tif' | grep -Eq '^rmse +0\$'"
"$TD" mosaic "$T/a.tif" "$T/b.tif" -o "$T/m.vrt" -q
check "mosaic .vrt: sources relative to it, GDAL reads it" \
  "grep -q 'relativeToVRT=\"1\">a.tif' '$T/m.vrt' && gdalinfo '$T/m.vrt' | grep -q 'Size is 367, 359'"

# a series: the Front Range sheet (labels printed) cut into 3 x 2 sheets
# that keep their place; alone half of them cannot start, with
# --neighbours they take their heights across the shared edges
FR=tests/data/dems/frontrange_srtm3.tif
[ -e "$FR" ] || FR=../shared/dems/frontrange_srtm3.tif
"$BUILD/tdgen" --dem-in "$FR" --scale 10 --width 1.8 --index-width 3.2 --labels 3 \
    --label-bend 40 --label-font dejavu --blur 0.8 --noise 8 --tiff \
    -o "$T/big.tif" --dem "$T/truth.tif" -q
echo "sheet,options" >"$T/s.csv"
for r in 0 1; do for c in 0 1 2; do
  gdal_translate -q -srcwin $((c * 800)) $((r * 720)) 800 720 "$T/big.tif" "$T/t$r$c.tif"
  echo "t$r$c.tif," >>"$T/s.csv"
done; done
"$TD" batch "$T/s.csv" --out "$T/s1" --jobs 2 -q
check "a series alone: 3 of 6 sheets cannot start" "[ \$? = 1 ] && [ \$(grep -c '\"status\": \"failed\"' '$T/s1/batch.log') = 3 ]"
"$TD" batch "$T/s.csv" --out "$T/s2" --jobs 2 --neighbours -q
check "--neighbours: all 6 labelled, 3 from their neighbours, exit 0" \
  "[ \$? = 0 ] && [ \$(grep -c '\"heights_from\"' '$T/s2/batch.log') = 3 ]"
"$TD" mosaic "$T"/s2/*/dem.tif -o "$T/series.tif" -q
rmse=$("$TD" compare "$T/series.tif" "$T/truth.tif" | awk '$1 == "rmse" { print $2 }')
cov=$("$TD" compare "$T/series.tif" "$T/truth.tif" | awk '$1 == "coverage" { print $2 }')
"$TD" run "$T/big.tif" -o "$T/whole.tif" -q
whole=$("$TD" compare "$T/whole.tif" "$T/truth.tif" | awk '$1 == "rmse" { print $2 }')
check "the series' mosaic against the true DEM: RMSE $rmse m, within 5 % of the whole sheet run as one ($whole m); coverage $cov (> 0.998: the seams fill the edges)" \
  "awk -v r='$rmse' -v w='$whole' -v c='$cov' 'BEGIN { exit !(r > 0 && r <= 1.05 * w && c > 0.998) }'"
gdal_translate -q -of AAIGrid "$T/series.tif" "$T/series.asc"
steps=$(awk 'NR > 6 { r = NR - 7; for (c = 1; c <= NF; c++) {
    if (c > 1 && (c - 1) % 800 == 0) { e += ($c > p[c-1] ? $c - p[c-1] : p[c-1] - $c); ne++ }
    else if (c > 1 && (c - 1) % 800 == 400) { i += ($c > p[c-1] ? $c - p[c-1] : p[c-1] - $c); ni++ }
    if (r > 0 && r % 720 == 0) { e += ($c > q[c] ? $c - q[c] : q[c] - $c); ne++ }
    else if (r > 0 && r % 720 == 360) { i += ($c > q[c] ? $c - q[c] : q[c] - $c); ni++ }
    p[c] = $c }
  for (c = 1; c <= NF; c++) q[c] = $c }
  END { printf "%.3f %.3f", e / ne, i / ni }' "$T/series.asc")
check "the steps across the sheet edges no larger than inside a sheet (mean |step| across, inside: $steps m)" \
  "echo $steps | awk '{ exit !(\$1 > 0 && \$1 <= \$2) }'"
check "the joint solve: the six sheets labelled as one, their DEMs cut from one interpolation" \
  "grep '\"step\": \"joint\", \"status\": \"ok\", \"sheets\": 6' '$T/s2/batch.log' | grep -q '\"dems\": \"one interpolation\"'"
"$TD" batch "$T/s.csv" --out "$T/s5" --jobs 2 --neighbours --no-joint -q
check "--no-joint: seams, each sheet interpolated again beside its neighbours" \
  "[ \$(grep '\"step\": \"seams\", \"status\": \"ok\"' '$T/s5/batch.log' | wc -l) = 6 ] && grep '\"sheet\": \"[^\"]*t11.tif\", \"step\"' '$T/s5/batch.log' | grep -q '\"beside\": \"t00, t01, t02, t10, t12\"'"
cross=$(grep '"edge"' "$T/s2/batch.log" | sed 's/.*"crossings": \([0-9]*\).*/\1/' | awk '{ s += $1 } END { print s + 0 }')
conf=$(grep '"edge"' "$T/s2/batch.log" | sed 's/.*"conflicting": \([0-9]*\).*/\1/' | awk '{ s += $1 } END { print s + 0 }')
check "edge matching: 11 neighbour pairs, $cross contour crossings paired (> 80), $conf with two heights (<= 1)" \
  "[ \$(grep -c '\"edge\": \\[\"t' '$T/s2/batch.log') = 11 ] && [ $cross -gt 80 ] && [ $conf -le 1 ]"
"$TD" batch "$T/s.csv" --out "$T/s6" --jobs 2 --neighbours --joint-cells 2e6 -q
"$TD" mosaic "$T"/s6/*/dem.tif -o "$T/series6.tif" -q
rmse6=$("$TD" compare "$T/series6.tif" "$T/truth.tif" | awk '$1 == "rmse" { print $2 }')
check "--joint-cells: the series solved in 2 blocks (4 and 2 sheets, the second with the 2 solved sheets beside it as evidence), the DEMs from one interpolation after them, the mosaic RMSE $rmse6 m within 5 % of the whole sheet's" \
  "[ \$(grep '\"step\": \"joint\", \"status\": \"ok\"' '$T/s6/batch.log' | grep -c '\"block\"') = 2 ] && grep -q '\"sheets\": 4,.*\"block\": 0, \"beside\": 0' '$T/s6/batch.log' && grep -q '\"sheets\": 2,.*\"block\": 1, \"beside\": 2' '$T/s6/batch.log' && grep -q '\"step\": \"dems\", \"status\": \"ok\", \"sheets\": 6' '$T/s6/batch.log' && awk -v r='$rmse6' -v w='$whole' 'BEGIN { exit !(r > 0 && r <= 1.05 * w) }'"
"$TD" batch "$T/s.csv" --out "$T/s7" --jobs 1 --neighbours -q &
bp=$!
k=0
while [ $k -lt 600 ]; do
  n=$(grep -c '"status": "ok"' "$T/s7/batch.log" 2>/dev/null)
  [ "${n:-0}" -ge 2 ] && break
  sleep 0.1; k=$((k + 1))
done
# and a third sheet running (between two sheets nothing runs to interrupt)
k=0
while [ $k -lt 600 ] && ! grep -asl 's7/[t]' /proc/[0-9]*/cmdline >/dev/null; do
  sleep 0.05; k=$((k + 1))
done
kill $bp; wait $bp; krc=$?
check "batch killed after two sheets (SIGTERM): exit 143, the running sheet logged as interrupted, no run left behind" \
  "[ $krc = 143 ] && grep -q '\"status\": \"interrupted\"' '$T/s7/batch.log' && ! grep -asl 's7/[t]' /proc/[0-9]*/cmdline >/dev/null"
"$TD" batch "$T/s.csv" --out "$T/s7" --jobs 1 --neighbours --resume -q
check "then --resume: the finished sheets skipped, the same DEMs as a run never stopped" \
  "[ \$(grep -c '\"status\": \"skipped\"' '$T/s7/batch.log') -ge 2 ] && cmp -s '$T/s7/t11/dem.tif' '$T/s2/t11/dem.tif' && cmp -s '$T/s7/t00/dem.tif' '$T/s2/t00/dem.tif' && cmp -s '$T/s7/t12/dem.tif' '$T/s2/t12/dem.tif'"
cp "$T/s2/t11/dem.tif" "$T/t11_first.tif"
"$TD" batch "$T/s.csv" --out "$T/s2" --jobs 2 --neighbours --resume -q
check "--resume on a series: the runs skipped, the joint solve from the same lines, the same DEMs" \
  "[ \$(grep -c '\"status\": \"skipped\"' '$T/s2/batch.log') = 6 ] && cmp -s '$T/s2/t11/dem.tif' '$T/t11_first.tif'"
(cd "$T" && "$TDA" batch --emit parallel s.csv --out spar >sjobs.txt)
if command -v parallel >/dev/null 2>&1; then
  (cd "$T" && parallel -j 2 <sjobs.txt >/dev/null 2>&1)
else
  (cd "$T" && sh sjobs.txt >/dev/null 2>&1)
fi
(cd "$T" && "$TDA" batch --joint-only s.csv --out spar -q)
"$TD" batch "$T/s.csv" --out "$T/s4" --jobs 2 -q
check "the emitted jobs, then batch --joint-only: the DEMs batch makes itself" \
  "grep -q '\"step\": \"joint\", \"status\": \"ok\"' '$T/spar/batch.log' && cmp -s '$T/spar/t00/dem.tif' '$T/s4/t00/dem.tif' && cmp -s '$T/spar/t10/dem.tif' '$T/s4/t10/dem.tif'"
(cd "$T" && "$TDA" batch --emit parallel s.csv --out snb --neighbours >snjobs.txt)
(cd "$T" && sh snjobs.txt >/dev/null 2>&1)
(cd "$T" && "$TDA" batch --joint-only s.csv --out snb --neighbours -q)
check "--emit with --neighbours: the jobs tolerate the sheets that cannot start, the joint step seeds and runs them: the DEMs of batch --neighbours" \
  "grep -q '|| :\$' '$T/snjobs.txt' && [ \$(grep -c '\"heights_from\"' '$T/snb/batch.log') = 3 ] && cmp -s '$T/snb/t11/dem.tif' '$T/s2/t11/dem.tif' && cmp -s '$T/snb/t00/dem.tif' '$T/s2/t00/dem.tif'"
(cd "$T" && "$TDA" batch --emit make s.csv --out smk >s.mk)
check "--emit make: the joint step after every sheet" \
  "grep -q 'smk/joint.done: smk/t00/dem.tif' '$T/s.mk' && grep -q 'batch --joint-only s.csv --out smk' '$T/s.mk' && (cd '$T' && make -n -f s.mk >/dev/null 2>&1)"
"$TD" batch "$T/s.csv" --out "$T/s3" --jobs 2 --neighbours --no-seams --no-joint -q
"$TD" mosaic "$T"/s3/*/dem.tif -o "$T/series3.tif" -q
cov3=$("$TD" compare "$T/series3.tif" "$T/truth.tif" | awk '$1 == "coverage" { print $2 }')
rmse3=$("$TD" compare "$T/series3.tif" "$T/truth.tif" | awk '$1 == "rmse" { print $2 }')
check "--no-seams --no-joint: each sheet as its own run left it (RMSE $rmse3 > $rmse, coverage $cov3 < $cov)" \
  "! grep -q '\"step\": \"seams\"' '$T/s3/batch.log' && awk -v a='$cov3' -v b='$cov' -v r3='$rmse3' -v r='$rmse' 'BEGIN { exit !(a < b && r3 > r) }'"
gdal_translate -q -srcwin 400 0 800 720 "$T/big.tif" "$T/o1.tif"
printf 'sheet,options\nt00.tif,--interval 50 --known 300,300,2700\no1.tif,--interval 50 --known 300,300,2700\n' >"$T/ov.csv"
"$TD" batch "$T/ov.csv" --out "$T/ov" -q
check "two sheets that overlap: said in the log, not used for each other" \
  "grep -q 'overlaps .*o1.tif instead of sharing an edge' '$T/ov/batch.log' && ! grep -q '\"step\": \"\\(seams\\|interp\\|joint\\)\"' '$T/ov/batch.log'"
gdal_translate -q -a_srs EPSG:32613 "$T/t10.tif" "$T/c10.tif"
printf 'sheet,options\nt00.tif,\nc10.tif,\n' >"$T/crs.csv"
"$TD" batch "$T/crs.csv" --out "$T/crs" -q
check "two sheets in different CRSs: both run, a line in the log names both, not matched with each other" \
  "[ \$? = 0 ] && grep -q 'in a CRS without an EPSG code, .*c10.tif in EPSG:32613: not matched' '$T/crs/batch.log' && ! grep -q '\"edge\": ' '$T/crs/batch.log'"
printf 'sheet,options\nnope.tif,\nt00.tif,--bogus-opt 3\nt02.tif,\n' >"$T/bad.csv"
"$TD" batch "$T/bad.csv" --out "$T/bad" --no-joint --no-seams -q
check "a missing sheet and a line with a bad option: each a failed line naming it, the good sheet done, exit 1" \
  "[ \$? = 1 ] && grep -q 'nope.tif: cannot open' '$T/bad/batch.log' && grep -q \"bad or incomplete option '--bogus-opt'\" '$T/bad/batch.log' && grep 't02.tif' '$T/bad/batch.log' | grep -q '\"status\": \"ok\"'"
"$TD" interp "$T/s2/t00/lines.geojson" --like "$T/elk6.png" --beside "$T/s2/t01/lines.geojson" -o "$T/x.tif" 2>"$T/err"
check "interp --beside on a sheet without georeferencing: one error naming it" \
  "[ \$? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'elk6.png: not georeferenced' '$T/err' && [ ! -e '$T/x.tif' ]"

"$TD" batch "$T/missing.csv" --out "$T/o2" 2>"$T/err"
check "a missing manifest: one error naming it, exit 1" "[ \$? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'missing.csv' '$T/err'"
printf 'elk6.png,\nsub/elk6.png,\n' >"$T/dup.csv"
"$TD" batch "$T/dup.csv" --out "$T/o2" 2>"$T/err"
check "two sheets of one name: refused" "[ \$? = 1 ] && grep -q 'two sheets named elk6' '$T/err' && [ ! -e '$T/o2' ]"
"$TD" mosaic "$T/a.tif" -o "$T/m.png" 2>"$T/err"
check "mosaic to another format: refused" "[ \$? = 1 ] && grep -q '.vrt or .tif' '$T/err'"

e2e_summary
