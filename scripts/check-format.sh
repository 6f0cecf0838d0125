#!/usr/bin/env bash
# Fails when a C++ file differs from what clang-format (../.clang-format) would write.
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t files < <(git ls-files '*.h' '*.cpp')
((${#files[@]} == 0)) && exit 0
clang-format --dry-run --Werror "${files[@]}"
