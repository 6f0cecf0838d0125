#!/usr/bin/env bash
# The training runs of profile-guided optimisation (scripts/pgo.sh): what the instrumented
# certray given as $1 is made to do while it counts its branches and calls. One thread, so that
# the counts are exact and the same on every run.
#
# Deliberately not the scenes of issue #16's measured goals — the Barth sextic, the Fidget bear
# and colonnade, prospero: their times in docs/benchmarks.md are of a build that never ran them.
# The rest of the gallery, as pinhole images and orthographic heightmaps, zero sets and solids;
# certified ray queries and the approximate tracers on scenes/rays.csv; a 2D image.
set -euo pipefail
certray=$1
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cd "$(dirname "$0")/.."
render() { "$certray" render "$@" --threads 1 -q -o "$out/image.png" >/dev/null; }
# Smooth lists: the algebraic surfaces and the .expr scenes, pinhole, zero sets.
for scene in scenes/chmutov6.vm scenes/clebsch_cubic.vm scenes/kummer_quartic.vm scenes/mitchell.vm \
    scenes/steiner_roman.vm scenes/tangle_knoll.vm scenes/tanglecube.vm scenes/sphere.expr \
    scenes/torus.expr scenes/blobs.expr scenes/csg.expr scenes/gyroid.expr; do
    render "$scene" --surface zero --size 256x256
done
# Solids, pinhole and heightmaps: min/max lists with kinks, folded and pruned (CSG trees, the
# particles' blend), as the Fidget models are.
for scene in scenes/tanglecube.vm scenes/chmutov6.vm scenes/test.json scenes/csg.expr \
    scenes/particles.txt scenes/gyroid.expr; do
    render "$scene" --surface solid --size 256x256
    render "$scene" --surface solid --size 192x192 --camera ortho
done
render scenes/molecule.json --size 64x48
render scenes/molecule.json --size 48x48 --camera ortho
render scenes/fidget/quarter.vm --size 256x256
for scene in scenes/kummer_quartic.vm scenes/torus.expr scenes/csg.expr; do
    for method in certified sphere segment march certified-octree; do
        "$certray" query "$scene" --rays scenes/rays.csv --method "$method" --threads 1 -q \
            --out "$out/hits.csv" >/dev/null
    done
done
