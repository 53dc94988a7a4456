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
# Three known heights on the lines that leave the sheet (which way the tilt
# rises cannot be told from the topology alone) and the depression marked.
echo "== topodig run samples/hills.png -> DEM (interval 20 m, 3 known points, a depression)"
"$TD" run samples/hills.png -o "$OUT/hills-dem.tif" --interval 20 \
    --known 123.5,264,120 --known 267.5,244.2,200 --known 561.5,77.1,240 \
    --depressions 205,336 --debug-dir "$OUT/hills-run"
echo "== topodig compare with the true surface (samples/hills.tif)"
"$TD" compare "$OUT/hills-dem.tif" samples/hills.tif
echo "== topodig render"
"$TD" render "$OUT/hills-dem.tif" -o "$OUT/hills-relief.png" --style hillshade --contours 20
# A sheet drawn from a real DEM (Colorado Front Range, SRTM) with printed
# height labels, scanned: no option needed, the labels are read.
echo "== tdgen: a labelled, scanned sheet from a real DEM (tests/data/dems/frontrange_srtm3.tif)"
"$BUILD/tdgen" --dem-in tests/data/dems/frontrange_srtm3.tif --scale 10 \
    --width 1.8 --index-width 3.2 --labels 3 --label-bend 40 --label-font dejavu \
    --blur 0.8 --noise 8 --specks 200 --breaks 30 --break-len 3,10 \
    -o "$OUT/frontrange.png" --dem "$OUT/frontrange-truth.tif" -q
echo "== topodig run $OUT/frontrange.png -> DEM (no options: labels read, interval inferred)"
"$TD" run "$OUT/frontrange.png" -o "$OUT/frontrange-dem.tif" --debug-dir "$OUT/frontrange-run"
"$TD" compare "$OUT/frontrange-dem.tif" "$OUT/frontrange-truth.tif"
echo "== topodig view, mesh and report: teaching material from that DEM"
"$TD" view "$OUT/frontrange-dem.tif" -o "$OUT/frontrange-view.png" --drape tint -q
# the sheet has no georeferencing: a pixel is 9 m (SRTM 3" drawn 10x)
"$TD" mesh "$OUT/frontrange-dem.tif" -o "$OUT/frontrange.stl" --step 2 --print-size 150 --cellsize 9 --exaggeration 2
"$TD" report "$OUT/frontrange.png" -o "$OUT/frontrange-report.pdf" -q
echo
echo "wrote $OUT/: hills.geojson, brown.geojson (one LineString per contour),"
echo "  *-debug/overlay.png (traced lines in their own colours, red boxes at open ends),"
echo "  hills-dem.tif (float32 GeoTIFF DEM) and hills-relief.png (shaded relief),"
echo "  frontrange-dem.tif from the labelled sheet frontrange.png, and in *-run/"
echo "  heights.png (lines coloured by height, labels boxed) and labels.geojson;"
echo "  frontrange-view.png (3-D view), frontrange.stl (printable, 150 mm) and"
echo "  frontrange-report.pdf (a one-page handout)."
