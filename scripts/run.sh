#!/usr/bin/env bash
# Builds the certray executable (Release) and runs the main job over the scene gallery: for each
# scene, the tape, a proven enclosure of f and a Lipschitz bound over its bounds, the evaluation
# speed, and how far interval pruning shortens the tape per subdivision level.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target certray_cli
build/apps/certray inspect scenes/*.expr scenes/[a-o]*.vm scenes/[q-z]*.vm --bounds -2 2 --levels 4
build/apps/certray inspect scenes/prospero.vm --bounds -1 1 --levels 6
