#!/usr/bin/env bash
# Profile-guided optimisation, step one: builds an instrumented certray in build-pgo/ and runs the
# training (scripts/pgo-train.sh), which leaves its counts in build-pgo/profile/. Step two is a
# build configured with -DCERTRAY_PGO=use -DCERTRAY_PGO_DIR="$PWD/build-pgo/profile".
# build-pgo/profile/stamp.h names the counts by their hash; every file of a CERTRAY_PGO=use build
# includes it, so that new counts recompile them all and the same counts recompile nothing.
# Optional: the scripts' builds do not use it (docs/benchmarks.md, session 29: the times move by
# −6% to +5% per scene with the training's mix).
set -euo pipefail
cd "$(dirname "$0")/.."
profile="$PWD/build-pgo/profile"
cmake -S . -B build-pgo -G Ninja -DCMAKE_BUILD_TYPE=Release -DCERTRAY_PGO=generate \
    -DCERTRAY_PGO_DIR="$profile" -DCERTRAY_TESTS=OFF -DCERTRAY_BENCH=OFF -DCERTRAY_PYTHON=OFF \
    -DCERTRAY_INSTALL=OFF >/dev/null
cmake --build build-pgo -j"$(nproc)" --target certray_cli
certray=build-pgo/apps/certray
trained="$profile/trained"
if [[ -f "$trained" && ! "$certray" -nt "$trained" && ! scripts/pgo-train.sh -nt "$trained" ]]; then
    echo "pgo: the profile is up to date (build-pgo/profile)"
    exit 0
fi
find "$profile" -name '*.gcda' -delete 2>/dev/null || true
start=$(date +%s)
scripts/pgo-train.sh "$certray"
mapfile -t counts < <(find "$profile" -name '*.gcda' | sort)
if [[ ${#counts[@]} -eq 0 ]]; then
    echo "pgo: the training left no counts in $profile" >&2
    exit 1
fi
stamp="// certray's profile for -fprofile-use: $(cat "${counts[@]}" | sha256sum | cut -c1-16)"
if [[ ! -f "$profile/stamp.h" || "$(cat "$profile/stamp.h")" != "$stamp" ]]; then
    echo "$stamp" >"$profile/stamp.h"
fi
touch "$trained"
echo "pgo: trained in $(($(date +%s) - start)) s: ${#counts[@]} files of counts in build-pgo/profile"
