#!/usr/bin/env bash
# Installs everything carve needs to build and test, from Debian 12 packages only.
set -euo pipefail
pkgs=(build-essential cmake ninja-build pkg-config libpolyclipping-dev libboost-dev nlohmann-json3-dev
      libcli11-dev libfmt-dev libzip-dev zlib1g-dev libpng-dev libgtest-dev libgmock-dev
      libbenchmark-dev libjemalloc-dev libtbb-dev libeigen3-dev python3 python3-numpy python3-matplotlib clang-14 libclang-rt-14-dev
      clang-format-14)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
