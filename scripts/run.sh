#!/usr/bin/env bash
# Builds the certray executable (Release) and runs the main job over the scene gallery: for each
# scene, the tape, a proven enclosure of f and a Lipschitz bound over its bounds, the evaluation
# speed, and how far interval pruning shortens the tape per subdivision level; certified ray
# queries on every 3D scene; and the gallery rendered to out/gallery/*.png (certified, shaded and
# with the per-pixel evaluation count; prospero as a 2D image: the sign of f at each pixel centre).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target certray_cli
build/apps/certray inspect scenes/*.expr scenes/[a-o]*.vm scenes/[q-z]*.vm --bounds -2 2 --levels 4
build/apps/certray inspect scenes/prospero.vm --bounds -1 1 --levels 6
# Certified ray queries: 256 rays of scenes/rays.csv against each 3D scene of the gallery.
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for scene in scenes/*.expr scenes/[a-o]*.vm scenes/[q-z]*.vm; do
    build/apps/certray query "$scene" --rays scenes/rays.csv --method certified \
        --out "$out/hits.csv" --stats "$out/stats.json"
    python3 - "$scene" "$out/stats.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[2]))
st, ev = s["status"], s["evaluations_per_ray"]
print(f"{sys.argv[1]:28s} certified: {st['hit']:3d} hit {st['miss']:3d} miss {st['unknown']:3d} unknown"
      f"  evaluations/ray mean {ev['mean']:7.1f} max {ev['max']:5d}  {s['seconds'] * 1e3:7.1f} ms")
PY
done
# The 10⁴-sphere CSG of the stress suite with bounding volumes: each ray's tape keeps only the
# spheres whose boxes it meets (certified-bvh), against certified (these 256 parallel rays are
# answered together by the coherent walk, with the 50,501-instruction tape pruned per box).
for method in certified-bvh certified; do
    build/apps/certray query scenes/stress/deep_csg.expr --rays scenes/stress/deep_csg_rays.csv \
        --method "$method" --out "$out/hits-$method.csv" --stats "$out/stats.json"
    python3 - "$method" "$out/stats.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[2]))
st = s["status"]
print(f"deep_csg.expr (10^4 spheres) {sys.argv[1]:14s}: {st['hit']:3d} hit {st['miss']:3d} miss "
      f"{st['unknown']:3d} unknown  {s['seconds'] * 1e3:8.1f} ms")
PY
done
cmp -s "$out/hits-certified-bvh.csv" "$out/hits-certified.csv" &&
    echo "deep_csg.expr: certified-bvh and certified give identical answers" ||
    echo "deep_csg.expr: answers differ in their enclosures (both certified; see the CSVs)"
# The gallery, rendered: every pixel of the 3D images is a certified answer (hit, miss, or an
# unknown drawn in magenta).
mkdir -p out/gallery
# The algebraic surfaces are zero sets (their f < 0 is unbounded): drawn as --surface zero.
for scene in scenes/*.expr scenes/[a-o]*.vm scenes/[q-s]*.vm scenes/tangle_knoll.vm; do
    name=$(basename "${scene%.*}")
    printf '%-28s ' "$scene"
    build/apps/certray render "$scene" -o "out/gallery/$name.png" --size 320x240 --method certified \
        --surface zero -q
    printf '%-28s ' "$scene (steps)"
    build/apps/certray render "$scene" -o "out/gallery/$name-steps.png" --size 320x240 \
        --method certified --surface zero --aov steps -q
done
# Models as their authors made them (Fidget, Lipschitz-Pruning): the solid f < 0, as their
# renderers draw it, framed by the bounds the files give; the unknown count is in each line.
for scene in scenes/tanglecube.vm scenes/test.json; do
    name=$(basename "${scene%.*}")
    printf '%-28s ' "$scene"
    build/apps/certray render "$scene" -o "out/gallery/$name.png" --size 320x240 -q
done
printf '%-28s ' scenes/molecule.json
build/apps/certray render scenes/molecule.json -o out/gallery/molecule.png --size 96x72 -q
printf '%-28s ' "scenes/barth_sextic.vm (ortho)"
build/apps/certray render scenes/barth_sextic.vm -o out/gallery/barth_sextic-ortho.png --size 512x512 \
    --surface zero --camera ortho -q
printf '%-28s ' scenes/prospero.vm
build/apps/certray render scenes/prospero.vm -o out/gallery/prospero.png --size 1024x1024
echo "images in out/gallery/"
