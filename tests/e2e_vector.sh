#!/bin/sh
# End-to-end checks of the vector formats (GeoJSON, GeoPackage, Shapefile,
# DXF) and the frames: what scan, label and run write opens in ogrinfo with
# the same features, reads back into the same DEM, lies in the frame of the
# DEM (the pixel frame for a plain scan, the scan's CRS for a GeoTIFF),
# and bad vector input or output gets one error line and no file.
# Covers src/io/vector_ogr.c and the frames of src/io/georef.c.
BUILD=${BUILD:-build}
. tests/util/e2e.sh
TD="$BUILD/topodig"
T=$(mktemp -d "${TMPDIR:-/tmp}/tdvector.XXXXXX")
trap 'rm -rf "$T"' EXIT
pass=0; fail=0
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; }
check() { if eval "$2"; then ok "$1"; else bad "$1"; fi; }
count() { ogrinfo -ro -so -al "$1" 2>/dev/null | sed -n 's/^Feature Count: //p' | head -n 1; }

if ! command -v ogrinfo >/dev/null 2>&1; then
    echo "ogrinfo absent: vector checks skipped"
    echo "0 passed, 0 failed"
    exit 0
fi

K3="--known 123.5,263.996,120 --known 267.5,244.206,200 --known 561.5,77.084,240 --depressions 205,336"
"$TD" scan samples/hills.png -o "$T/lines.geojson" -q
n=$(count "$T/lines.geojson")
for e in gpkg shp dxf; do
    "$TD" scan samples/hills.png -o "$T/lines.$e" -q 2>"$T/err"
    check "scan -o lines.$e: exit 0, ogrinfo sees the same $n lines as the GeoJSON" \
        "[ \$? = 0 ] && [ '$(count "$T/lines.$e")' = '$n' ] && [ -n '$n' ] && [ '$n' -gt 10 ]"
done
check "GeoPackage and Shapefile in the pixel frame's engineering CRS, not WGS 84" \
    "ogrinfo -ro -so -al '$T/lines.gpkg' | grep -q 'topodig scan pixels' && ogrinfo -ro -so -al '$T/lines.shp' | grep -q 'topodig scan pixels' && ! ogrinfo -ro -so -al '$T/lines.gpkg' | grep -q 4326"
check "GeoPackage keeps the properties (height, height_source, closed, edge, width, depression)" \
    "ogrinfo -ro -so -al '$T/lines.gpkg' | grep -q '^height: Real' && ogrinfo -ro -so -al '$T/lines.gpkg' | grep -q '^height_source: String' && ogrinfo -ro -so -al '$T/lines.gpkg' | grep -q '^closed: Integer(Boolean)' && ogrinfo -ro -so -al '$T/lines.gpkg' | grep -q '^width: Real' && ogrinfo -ro -so -al '$T/lines.gpkg' | grep -q '^depression: Integer(Boolean)'"

# a short piece the scanner set aside ("piece": true, scan --pieces late)
# keeps its mark through a GeoPackage and back
sed '0,/"closed":false,/s//"closed":false,"piece":true,/' "$T/lines.geojson" >"$T/pc.geojson"
"$TD" label "$T/pc.geojson" -o "$T/pc.gpkg" --interval 20 $K3 -q 2>"$T/err" &&
    "$TD" label "$T/pc.gpkg" -o "$T/pc2.geojson" --interval 20 $K3 -q 2>>"$T/err"
rc=$?
check "a piece's mark through .gpkg and back (piece: Integer(Boolean), one line)" \
    "[ $rc = 0 ] && [ \$(grep -c '\"piece\":true' '$T/pc.geojson') = 1 ] && ogrinfo -ro -so -al '$T/pc.gpkg' | grep -q '^piece: Integer(Boolean)' && [ \$(grep -o '\"piece\":true' '$T/pc2.geojson' | wc -l) = 1 ]"

# label from each format, interp from each: the same DEM
"$TD" label "$T/lines.geojson" -o "$T/lab.geojson" --interval 20 $K3 -q
"$TD" interp "$T/lab.geojson" -o "$T/ref.tif" --like samples/hills.png -q
for e in gpkg shp dxf; do
    "$TD" label "$T/lines.$e" -o "$T/lab.$e" --interval 20 $K3 -q 2>"$T/err" &&
        "$TD" interp "$T/lab.$e" -o "$T/dem-$e.tif" --like samples/hills.png -q 2>>"$T/err"
    rc=$?
    "$TD" compare "$T/ref.tif" "$T/dem-$e.tif" --json >"$T/c.json" 2>/dev/null
    check "label and interp through .$e give the GeoJSON's DEM exactly (rmse 0)" \
        "[ $rc = 0 ] && grep -q '\"rmse\": *0[,}]' '$T/c.json'"
done
check "DXF: 3-D polylines at their heights (z of a vertex = a contour height)" \
    "ogrinfo -ro -al '$T/lab.dxf' 2>/dev/null | grep -m1 'LINESTRING Z' | grep -Eq '\\(-?[0-9.]+ -[0-9.]+ [0-9]+0,'"

# ridges by extension: the same paths in GeoPackage (3-D) and GeoJSON
"$TD" ridges "$T/lab.geojson" -o "$T/r.geojson" -q
"$TD" ridges "$T/lab.geojson" -o "$T/r.gpkg" -q
check "ridges -o .gpkg: the GeoJSON's $(count "$T/r.geojson") paths as 3-D lines with kind and tree" \
    "[ '$(count "$T/r.gpkg")' = '$(count "$T/r.geojson")' ] && [ '$(count "$T/r.geojson")' -gt 2 ] && ogrinfo -ro -so -al '$T/r.gpkg' | grep -q '3D Line String' && ogrinfo -ro -so -al '$T/r.gpkg' | grep -q '^kind: String'"

# run --save-lines LINES.gpkg: the vertices sampled on the DEM give their heights
"$TD" run samples/hills.png -o "$T/run.tif" --interval 20 $K3 --save-lines "$T/run.gpkg" -q
set -- $(heights_on_dem "$T/run.gpkg" "$T/run.tif"); hit=$1; nv=$2
check "run --save-lines .gpkg: $hit of $nv lines sampled on the DEM through its geotransform give their own height" \
    "[ $nv -ge 10 ] && [ $hit -ge $((nv - 1)) ]"

# a georeferenced scan: lines in its CRS, read back to the same DEM
gdal_translate -q -a_srs EPSG:32633 -a_ullr 500000 4000450 500600 4000000 samples/hills.png "$T/geo.tif" 2>/dev/null
if [ -f "$T/geo.tif" ]; then
    "$TD" scan "$T/geo.tif" -o "$T/geo.gpkg" -q
    check "a GeoTIFF scan's GeoPackage is in its CRS (EPSG:32633) and map units" \
        "ogrinfo -ro -so -al '$T/geo.gpkg' | grep -q 'UTM zone 33N' && ogrinfo -ro -so -al '$T/geo.gpkg' | grep -q 'Extent: (500000'"
    "$TD" interp "$T/lab.gpkg" -o "$T/geo-dem.tif" --like "$T/geo.tif" -q
    check "interp --like a GeoTIFF: the DEM in its CRS" \
        "gdalinfo '$T/geo-dem.tif' | grep -q 'UTM zone 33N' && gdalinfo '$T/geo-dem.tif' | grep -q 'Origin = (500000'"
fi

# bad input and output
printf 'not a geopackage' >"$T/bad.gpkg"
"$TD" label "$T/bad.gpkg" -o "$T/o.gpkg" --interval 20 $K3 2>"$T/err"
check "a corrupt .gpkg: exit 1, one line naming it, no output" \
    "[ \$? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'bad.gpkg' '$T/err' && [ ! -e '$T/o.gpkg' ]"
"$TD" scan samples/hills.png -o "$T/x.kml" 2>"$T/err"
check "an unknown vector extension: exit 1, one line naming the formats" \
    "[ \$? = 1 ] && [ \$(wc -l <'$T/err') = 1 ] && grep -q 'gpkg' '$T/err' && [ ! -e '$T/x.kml' ]"
"$TD" scan samples/hills.png -o "$T/none/x.gpkg" 2>"$T/err"
check "a .gpkg in a missing folder: exit 1, one line" "[ \$? = 1 ] && [ \$(wc -l <'$T/err') = 1 ]"
cp "$T/lab.gpkg" "$T/keep.gpkg"
"$TD" label "$T/bad.gpkg" -o "$T/lab.gpkg" --interval 20 $K3 2>/dev/null
check "a failed label leaves the existing .gpkg as it was" "cmp -s '$T/lab.gpkg' '$T/keep.gpkg'"
check "no temporary folders left behind" "[ -z \"\$(ls -d '$T'/*.tmp.* 2>/dev/null)\" ]"

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
