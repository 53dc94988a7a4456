#!/bin/sh
# Make the two sample sheets in samples/ with build/tdgen (run `make all`
# first).  Usage: sh samples/make_samples.sh [BUILD_DIR]
set -e
B=${1:-build}
D=$(dirname "$0")

# Grey hills: 600x450, 2 px lines with a few 1-3 px breaks, light blur and
# noise, a few specks.  Interval chosen automatically (20 m at this size).
"$B/tdgen" -o "$D/hills.png" --truth "$D/hills.geojson" --dem "$D/hills.tif" \
    --size 600x450 --seed 7 --terrain hills --width 2 --breaks 6 \
    --break-len 1,3 --blur 0.6 --noise 6 --specks 12 --quiet

# Brown ink on cream with a blue river and black lettering, 3 px lines.
"$B/tdgen" -o "$D/brown.png" --truth "$D/brown.geojson" --dem "$D/brown.tif" \
    --size 700x500 --seed 12 --terrain hills --width 3 --colour \
    --distractors --breaks 4 --break-len 1,3 --blur 0.7 --noise 4 \
    --specks 8 --quiet
