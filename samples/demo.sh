#!/bin/sh
# make demo: scan the sample sheets (traced lines + debug pictures), then
# turn the grey sample into a DEM with `topodig run`, compare it with the
# true surface and render it; everything goes to out/demo/.
set -e
BUILD=${1:-build}
TD="$BUILD/topodig"
OUT=out/demo
mkdir -p "$OUT"
echo "== topodig scan samples/hills.png (grey sheet, 2-px lines, breaks)"
"$TD" scan samples/hills.png -o "$OUT/hills.geojson" --debug-dir "$OUT/hills-debug"
echo "== topodig scan samples/brown.png --ink brown (colour sheet, blue water, black text)"
"$TD" scan samples/brown.png -o "$OUT/brown.geojson" --ink brown --debug-dir "$OUT/brown-debug"
# Three known heights: two lines leaving the sheet (their slope direction
# cannot be told from the topology alone) and one ring of the depression.
echo "== topodig run samples/hills.png -> DEM (interval 20 m, 3 known points)"
"$TD" run samples/hills.png -o "$OUT/hills-dem.tif" --interval 20 \
    --known 123.5,264,120 --known 267.5,244.2,200 --known 199.5,318.1,40
echo "== topodig compare with the true surface (samples/hills.tif)"
"$TD" compare "$OUT/hills-dem.tif" samples/hills.tif
echo "== topodig render"
"$TD" render "$OUT/hills-dem.tif" -o "$OUT/hills-relief.png" --style hillshade --contours 20
echo
echo "wrote $OUT/: hills.geojson, brown.geojson (one LineString per contour),"
echo "  *-debug/overlay.png (traced lines in their own colours, red boxes at open ends),"
echo "  hills-dem.tif (float32 GeoTIFF DEM) and hills-relief.png (shaded relief)."
