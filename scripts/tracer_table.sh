#!/bin/bash
# scripts/tracer_table.sh — issue #14's table: every approximate tracer's render time against
# `certified` on the shared 3D models (scenes/), zero surface, 2 threads, one run each.
# Usage: scripts/tracer_table.sh [N] [EXTRA...]   (N: image side, default 512; EXTRA: more options
# for the approximate methods' renders, e.g. --per-ray). Needs build/apps/certray. Prints one
# markdown row per model: certified's seconds, then per method "seconds, unknown pixels (ratio×)";
# a render over 300 s is cut and shown as "> 300 s".
set -euo pipefail
cd "$(dirname "$0")/.."
N=${1:-512}
shift || true
B=build/apps/certray
for f in tanglecube barth_sextic chmutov6 clebsch_cubic kummer_quartic mitchell steiner_roman \
    tangle_knoll test particles molecule; do
    path=""
    for ext in vm json txt; do [ -f "scenes/$f.$ext" ] && path="scenes/$f.$ext"; done
    c=$($B render "$path" -o /tmp/tracer_table.png --size ${N}x$N --surface zero --threads 2 -q |
        tail -1 | sed 's/.* \([0-9.e-]*\) s on.*/\1/')
    line="| $f | $c s"
    for m in sphere enhanced bvh octree segment march; do
        out=$(timeout 300 $B render "$path" -o /tmp/tracer_table.png --size ${N}x$N --surface zero \
            --threads 2 -q --method $m "$@" | tail -1 || true)
        if [ -z "$out" ]; then line="$line | > 300 s"; continue; fi
        s=$(echo "$out" | sed 's/.* \([0-9.e-]*\) s on.*/\1/')
        u=$(echo "$out" | sed 's/.*unknown \([0-9]*\) pixels.*/\1/')
        line="$line | $s s, $u ($(python3 -c "print(f'{$s/$c:.1f}')")×)"
    done
    echo "$line |"
done
