#!/bin/bash
# scripts/coherent_table.sh — issue #16's ratio: the coherent certified image against one certified
# solve per pixel (`--per-ray`), per scene, pinhole camera, each scene's default surface and bounds
# (Fidget's models over [−1, 1]³), 2 threads.
# Usage: scripts/coherent_table.sh [N] [SCENE...]   (N: image side, default 512; SCENE: paths,
# default the gallery's 3D scenes and Fidget's two 3D models). Needs build/apps/certray. Prints one
# markdown row per scene: the coherent image's seconds (the faster of two runs) and evaluations per
# pixel, the per-ray image's seconds (one run) and evaluations per pixel, their ratio, and the
# unknown pixels of each; a per-ray image over 600 s is cut and shown as "> 600 s".
set -euo pipefail
cd "$(dirname "$0")/.."
N=${1:-512}
shift || true
B=build/apps/certray
scenes=("$@")
if [ ${#scenes[@]} -eq 0 ]; then
    scenes=(scenes/*.expr scenes/[a-o]*.vm scenes/[q-z]*.vm scenes/*.json scenes/particles.txt
        scenes/fidget/bear.vm scenes/fidget/colonnade.vm)
fi
field() { sed -n "s/.*$1 \([0-9.e+-]*\).*/\1/p"; }
echo "| scene | coherent: s, evals/px, unknown | per ray: s, evals/px, unknown | per ray / coherent |"
echo "| --- | --- | --- | --- |"
for path in "${scenes[@]}"; do
    opts=(--size "${N}x$N" --threads 2 -q -o /tmp/coherent_table.png)
    case "$path" in scenes/fidget/*) opts+=(--bounds -1 1) ;; esac
    out=$($B render "$path" "${opts[@]}" | tail -1)
    # 2D scenes (no z) have no 3D image: skipped.
    case "$out" in 3D*) ;; *) continue ;; esac
    c1=$(echo "$out" | sed 's/.* \([0-9.e-]*\) s on.*/\1/')
    c2=$($B render "$path" "${opts[@]}" | tail -1 | sed 's/.* \([0-9.e-]*\) s on.*/\1/')
    c=$(python3 -c "print(min($c1, $c2))")
    ce=$(echo "$out" | field "; per pixel")
    cu=$(echo "$out" | sed 's/.*unknown \([0-9]*\) pixels.*/\1/')
    pr=$(timeout 600 $B render "$path" "${opts[@]}" --per-ray | tail -1 || true)
    if [ -z "$pr" ]; then
        echo "| $path | $c s, $ce, $cu | > 600 s | > $(python3 -c "print(f'{600/$c:.0f}')")× |"
        continue
    fi
    p=$(echo "$pr" | sed 's/.* \([0-9.e-]*\) s on.*/\1/')
    pe=$(echo "$pr" | field "; per pixel")
    pu=$(echo "$pr" | sed 's/.*unknown \([0-9]*\) pixels.*/\1/')
    echo "| $path | $c s, $ce, $cu | $p s, $pe, $pu | $(python3 -c "print(f'{$p/$c:.1f}')")× |"
done
