#!/usr/bin/env bash
# Builds the tests with AddressSanitizer + UndefinedBehaviorSanitizer and runs the unit tests.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" \
    -DCERTRAY_SANITIZE=ON -DCERTRAY_BENCH=OFF -DCERTRAY_PYTHON=OFF -DCERTRAY_INSTALL=OFF \
    -DCERTRAY_RC_CASES=300 >/dev/null
cmake --build build-asan -j"$(nproc)"
# Fewer random cases than the Release run: the sanitizers look for memory errors, not rare inputs.
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-asan -j"$(nproc)" -L unit --output-on-failure
