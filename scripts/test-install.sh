#!/usr/bin/env bash
# Installs certray from a build tree into a temporary prefix, then builds and runs the examples
# against the installed package (find_package(certray)), builds hello_ray through pkg-config, and
# checks that a translation unit compiled with -ffast-math is refused.
#   scripts/test-install.sh BUILD_DIR
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "$1" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
test -f "$tmp/prefix/include/certray/certray.h"
test -f "$tmp/prefix/lib/cmake/certray/certrayConfig.cmake"
# The core needs neither CLI11 nor nlohmann-json (libpng only for certray::certray_png).
if grep -qiE "nlohmann|CLI11" "$tmp/prefix/lib/cmake/certray/"*.cmake; then
    echo "the installed package depends on CLI11 or nlohmann-json" >&2
    exit 1
fi

cmake -S "$root/examples" -B "$tmp/examples" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$tmp/prefix" >/dev/null
cmake --build "$tmp/examples" >/dev/null
"$tmp/examples/hello_ray" | tee "$tmp/hello.txt"
awk '$1 == "hit" && $NF == "(proven)" { gsub(/[\[\],]/, ""); if ($2 <= 2 && 2 <= $3) ok = 1 } END { exit !ok }' "$tmp/hello.txt"
"$tmp/examples/hello_ray" "$root/scenes/torus.expr"
"$tmp/examples/build_scene"
"$tmp/examples/render_scene" "$root/scenes/torus.expr" "$tmp/torus.png" 64x48
test -s "$tmp/torus.png"

# Without CMake: pkg-config gives the flags, -frounding-math and -ffp-contract=off among them.
export PKG_CONFIG_PATH="$tmp/prefix/lib/pkgconfig"
flags=$(pkg-config --cflags --libs certray)
case "$flags" in *-frounding-math*) ;; *) echo "pkg-config: no -frounding-math" >&2; exit 1 ;; esac
# shellcheck disable=SC2086
c++ "$root/examples/hello_ray.cpp" -o "$tmp/hello_pc" $flags
"$tmp/hello_pc" >/dev/null

# -ffast-math breaks directed rounding: the header refuses it.
if c++ -std=c++20 -ffast-math -fsyntax-only -I"$tmp/prefix/include" -I"$tmp/prefix/include/certray" \
    "$root/examples/hello_ray.cpp" 2>"$tmp/fast.txt"; then
    echo "a -ffast-math translation unit compiled" >&2
    exit 1
fi
grep -q "certray: this translation unit is compiled with -ffast-math" "$tmp/fast.txt"
# The Python module, installed for the system Python under the prefix.
if [[ -d "$tmp/prefix/lib/python3/dist-packages/certray" ]]; then
    PYTHONPATH="$tmp/prefix/lib/python3/dist-packages" /usr/bin/python3 "$root/examples/hello_ray.py" \
        | tee "$tmp/py.txt"
    grep -q "^proven" "$tmp/py.txt"
fi
echo "install test: examples built and run against the installed package; pkg-config; -ffast-math refused"
