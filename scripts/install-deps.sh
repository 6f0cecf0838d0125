#!/usr/bin/env bash
# Installs what certray needs from Debian 12, idempotently; silent when everything is there.
set -euo pipefail

packages=(
    cmake ninja-build ccache g++ clang clang-format libclang-rt-14-dev pkgconf python3
    libboost-dev libmpfr-dev libgmp-dev libeigen3-dev
    libgtest-dev librapidcheck-dev libbenchmark-dev
    libcli11-dev nlohmann-json3-dev libtbb-dev libpng-dev
    python3-matplotlib python3-mpmath
    python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest
)

missing=()
for p in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
        missing+=("$p")
    fi
done
((${#missing[@]} == 0)) && exit 0

echo "install-deps: installing ${missing[*]}" >&2
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
