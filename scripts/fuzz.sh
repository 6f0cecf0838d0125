#!/usr/bin/env bash
# Builds the libFuzzer target for the .expr parser and .vm importer with clang (if present) and
# runs it for a short time (FUZZ_SECONDS, default 30), seeded with the gallery scenes.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v clang++ >/dev/null; then
    echo "fuzz: clang++ not found, skipped" >&2
    exit 0
fi
out=build-fuzz
mkdir -p "$out/corpus"
clang++ -std=c++20 -O1 -g -frounding-math -ffp-contract=off -fsanitize=fuzzer,address,undefined \
    -I. tests/fuzz/expr_fuzz.cpp expr/graph.cpp expr/parser.cpp expr/vm_import.cpp \
    expr/printer.cpp -o "$out/expr_fuzz"
# Seeds: every scene, prefixed with the byte that selects its reader.
for f in scenes/*.expr tests/data/models/*.vm; do
    case "$f" in
        *.expr) { printf '\x00'; cat "$f"; } >"$out/corpus/$(basename "$f")" ;;
        *.vm) { printf '\x01'; head -c 4000 "$f"; } >"$out/corpus/$(basename "$f")" ;;
    esac
done
"$out/expr_fuzz" -max_total_time="${FUZZ_SECONDS:-30}" -max_len=4096 -timeout=10 \
    "$out/corpus" 2>&1 | tail -n 3
