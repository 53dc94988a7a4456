#!/bin/sh
# make demo: scan the two sample sheets and write the traced lines and the
# debug pictures into out/demo/.
set -e
BUILD=${1:-build}
OUT=out/demo
mkdir -p "$OUT"
echo "== topodig scan samples/hills.png (grey sheet, 2-px lines, breaks)"
"$BUILD/topodig" scan samples/hills.png -o "$OUT/hills.geojson" --debug-dir "$OUT/hills-debug"
echo "== topodig scan samples/brown.png --ink brown (colour sheet, blue water, black text)"
"$BUILD/topodig" scan samples/brown.png -o "$OUT/brown.geojson" --ink brown --debug-dir "$OUT/brown-debug"
echo
echo "wrote $OUT/hills.geojson and $OUT/brown.geojson (one LineString per contour);"
echo "look at $OUT/*-debug/overlay.png: every traced line in its own colour, red boxes at open ends."
