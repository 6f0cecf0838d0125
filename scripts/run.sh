#!/usr/bin/env bash
# Builds the certray executable (Release) and runs the main job. Installs missing Debian packages.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target certray_cli
build/apps/certray demo "$@"
