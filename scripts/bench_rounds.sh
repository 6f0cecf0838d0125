#!/usr/bin/env bash
# scripts/bench_rounds.sh — two or more builds of certray timed by one Google Benchmark filter in
# interleaved rounds, for a machine whose speed drifts (docs/benchmarks.md, session 25): each
# round runs every build's benchmark in turn, each its least of three repetitions; printed per
# build, the least and the median of the rounds' times (Google Benchmark's time column, real time).
# BENCH_CLOCK=cpu takes its CPU column instead: the process's CPU time (coherent_bench measures
# process time), which on this virtual machine drifts less than the wall clock while other guests
# load the host (docs/benchmarks.md, session 30); for one thread's work (threads:1) only, since
# idle pool threads that spin count too.
# Usage: scripts/bench_rounds.sh ROUNDS FILTER BENCH BUILD_DIR...
#   e.g. scripts/bench_rounds.sh 8 'BM_Coherent/scene:0/side:512/ortho:0/threads:1/image:1' \
#        coherent_bench ../build-before build
set -euo pipefail
if (($# < 4)); then
    sed -n '2,9p' "$0" >&2
    exit 2
fi
rounds=$1
filter=$2
bench=$3
shift 3
case ${BENCH_CLOCK:-real} in
    real) column=3 ;;
    cpu) column=4 ;;
    *)
        echo "bench_rounds: BENCH_CLOCK must be real or cpu, not '$BENCH_CLOCK'" >&2
        exit 2
        ;;
esac
declare -A times
run() {
    "$1/bench/$bench" --benchmark_filter="$filter" --benchmark_min_time=0.2 \
        --benchmark_repetitions=3 --benchmark_format=csv 2>/dev/null |
        grep -v '^name' | grep -v '_mean\|_median\|_stddev\|_cv' | cut -d, -f"$column" |
        sort -g | head -1
}
for ((i = 0; i < rounds; ++i)); do
    for dir in "$@"; do
        t=$(run "$dir")
        [[ -n $t ]] || { echo "bench_rounds: $dir/bench/$bench ran nothing for '$filter'" >&2; exit 1; }
        times[$dir]="${times[$dir]:-} $t"
    done
done
for dir in "$@"; do
    python3 -c "
import statistics, sys
v = sorted(float(x) for x in sys.argv[2].split())
print(f'{sys.argv[1]}: least {v[0]:.2f}, median {statistics.median(v):.2f}')" "$dir" "${times[$dir]}"
done
