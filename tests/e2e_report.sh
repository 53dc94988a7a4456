#!/bin/sh
# End-to-end checks of topodig report (src/cli/report.c,
# src/pipeline/report.c): a labelled, scanned sheet drawn from a real DEM
# to a one-page PDF that pdfinfo opens; rendered with pdftoppm, the four
# panels hold ink where the layout puts them and the gutters between them
# are blank; bad input (one error line, exit 1, no output written).
BUILD=${BUILD:-build}
TD="$BUILD/topodig"
T=$(mktemp -d "${TMPDIR:-/tmp}/tdrp.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/util/e2e.sh # ok, bad, check, e2e_summary
DEM=tests/data/dems/elkhorn_srtm3.tif
[ -e "$DEM" ] || DEM=../shared/dems/elkhorn_srtm3.tif

check "report --help" "$TD report --help | grep -q '^usage: topodig report'"
# run and report take the run options from one table (src/cli/run_opts.c)
opts() { "$TD" "$1" --help | grep -o '^ *--[a-z-]*' | tr -d ' ' | grep -v -e '^--paper$' -e '^--title$' -e '^--summary-json$' | sort; }
check "report takes exactly the options of run (run_opts.c)" \
  "[ \"\$(opts run)\" = \"\$(opts report)\" ] && opts report | grep -q -- --known && opts report | grep -q -- --method"
"$BUILD/tdgen" --dem-in "$DEM" --scale 6 --width 1.8 --index-width 3.2 \
    --labels 3 --label-bend 40 --label-font dejavu --blur 0.6 --noise 6 \
    -o "$T/sheet.png" -q
"$TD" report "$T/sheet.png" -o "$T/r.pdf" --interval 10 --title "Elkhorn" 2>"$T/err"
check "report: exit 0, one summary line" "[ \$? = 0 ] && [ \$(grep -c '^report:' '$T/err') = 1 ] && grep -q 'one page (A4)' '$T/err'"
if command -v pdfinfo >/dev/null 2>&1; then
  check "pdfinfo: one A4 page" \
    "pdfinfo '$T/r.pdf' | grep -Eq '^Pages: +1\$' && pdfinfo '$T/r.pdf' | grep -q '595.28 x 841.89'"
fi
if command -v pdftoppm >/dev/null 2>&1; then
  # 36 dpi: a point is half a pixel; the page 298 x 421.  The layout (A4):
  # panels at x 36 and 304.64 pt, y 78 and 344 pt, 254.64 x 236 pt.
  pdftoppm -r 36 -gray -singlefile "$T/r.pdf" "$T/p"
  W=$(sed -n 2p "$T/p.pgm" | cut -d' ' -f1); H=$(sed -n 2p "$T/p.pgm" | cut -d' ' -f2)
  tail -c $((W * H)) "$T/p.pgm" | od -An -tu1 -v -w"$W" >"$T/rows.txt"
  # share of pixels in the box x0..x1, y0..y1 (pixels) darker than 235
  dark() { awk -v x0="$1" -v x1="$2" -v y0="$3" -v y1="$4" 'NR - 1 >= y0 && NR - 1 <= y1 { for (i = x0 + 1; i <= x1 + 1; i++) { n++; if ($i < 235) d++ } } END { printf "%.3f", d / n }' "$T/rows.txt"; }
  for p in "a 22 141 43 152" "b 156 275 43 152" "c 22 141 176 285" "d 156 275 176 285"; do
    set -- $p
    v=$(dark "$2" "$3" "$4" "$5")
    check "panel ($1) holds ink where the layout puts it (dark share $v)" "awk -v v=$v 'BEGIN { exit !(v > 0.03) }'"
  done
  v=$(dark 147 150 40 290)
  check "the gutter between the columns is blank (dark share $v)" "awk -v v=$v 'BEGIN { exit !(v == 0) }'"
  v=$(dark 2 15 40 290)
  check "the left margin is blank (dark share $v)" "awk -v v=$v 'BEGIN { exit !(v == 0) }'"
fi

"$TD" report "$T/sheet.png" -o "$T/x.png" --interval 10 2>"$T/err"
check "a report not named .pdf: refused" "[ \$? = 1 ] && grep -q 'PDF' '$T/err' && [ ! -e '$T/x.png' ]"
printf 'not an image' >"$T/bad.png"
"$TD" report "$T/bad.png" -o "$T/x.pdf" 2>"$T/err"
check "a corrupt sheet: one error naming it, exit 1, no output" \
  "[ \$? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'bad.png' '$T/err' && [ ! -e '$T/x.pdf' ]"

e2e_summary
