#!/bin/sh
# check_layers.sh: the include rules of DESIGN.md, checked on every
# library and CLI source (make layers; part of make test).
#
#   src/cli -> src/pipeline -> {scanner, interp, src/<stage>} -> src/io -> src/core
#
# A file may include a header of its own folder or of a folder below its
# own; never one beside it (two stages) or above it, never another
# folder's private *_int.h, and always spelled from the repository root
# ("src/core/core.h", not "core.h" or "../core.h").  A folder of src/ has
# one public header named after it (src/flow/flow.h); scanner/ and interp/
# have one per step (scanner/thin.h) and interp/interp.h as the front door.
# Each folder is one
# test: "ok FOLDER" or one line per broken include.
cd "$(dirname "$0")/.." || exit 1

rank() {
    case "$1" in
    src/core) echo 0 ;;
    src/io) echo 1 ;;
    scanner | interp | src/erode | src/flow | src/sun | src/render | \
        src/mesh | src/compare | src/model) echo 2 ;;
    src/pipeline) echo 3 ;;
    src/cli) echo 4 ;;
    *) echo "" ;;
    esac
}

pass=0
fail=0
for dir in src/core src/io scanner interp src/erode src/flow src/sun \
    src/render src/compare src/model src/pipeline src/cli; do
    [ -d "$dir" ] || continue
    r=$(rank "$dir")
    bad=0
    for f in "$dir"/*.c "$dir"/*.h "$dir"/*.cpp; do
        [ -e "$f" ] || continue
        for inc in $(sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([^"]*\)".*/\1/p' "$f"); do
            why=""
            idir=$(dirname "$inc")
            ir=$(rank "$idir")
            if [ ! -f "$inc" ]; then
                why="not a path from the repository root"
            elif [ -z "$ir" ]; then
                why="$idir is not a library folder"
            elif [ "$idir" != "$dir" ]; then
                case "$inc" in
                *_int.h) why="private header of $idir" ;;
                esac
                if [ -z "$why" ] && [ "$ir" -ge "$r" ]; then
                    if [ "$ir" = "$r" ]; then
                        why="sideways: $dir and $idir are peers"
                    else
                        why="upwards: $idir is above $dir"
                    fi
                fi
            fi
            if [ -n "$why" ]; then
                echo "FAIL $f: #include \"$inc\": $why"
                bad=1
            fi
        done
    done
    case "$dir" in
    src/*)
        for f in "$dir"/*.h; do
            case "$f" in
            "$dir/$(basename "$dir").h" | *_int.h) ;;
            *) echo "FAIL $f: src/ folders have one public header, named after the folder"; bad=1 ;;
            esac
        done ;;
    esac
    if [ "$bad" = 0 ]; then
        echo "ok $dir"
        pass=$((pass + 1))
    else
        fail=$((fail + 1))
    fi
done
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
