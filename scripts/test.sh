#!/usr/bin/env bash
# Builds certray (Release, profile-guided: scripts/pgo.sh) and runs the whole test suite. Installs
# missing Debian packages first.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
# Profile-guided: an instrumented build trained on the gallery first (scripts/pgo.sh).
scripts/pgo.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DCERTRAY_PGO=use \
    -DCERTRAY_PGO_DIR="$PWD/build-pgo/profile" >/dev/null
cmake --build build -j"$(nproc)"
ctest --test-dir build -j"$(nproc)" --output-on-failure
