#!/bin/sh
# make bench: every benchmark in build-bench/bench/, with the machine named.
# Benchmarks print numbers; they never fail the build.
BUILD=${BUILD:-build-bench}
echo "machine: $(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | head -n 1), $(nproc) cores, $(free -g 2>/dev/null | awk '/^Mem:/{print $2}') GB"
echo "date: $(date -u +%Y-%m-%d)"
for b in "$BUILD"/bench/*; do
    [ -x "$b" ] || continue
    echo "== $(basename "$b")"
    "$b" --topodig "$BUILD/topodig" --dir "$BUILD/data" ${BENCH_ARGS:-} || echo "   (failed)"
done
exit 0
