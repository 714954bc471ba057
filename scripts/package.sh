#!/usr/bin/env bash
# Builds the Debian package build/carve_<version>_<arch>.deb (CPack, see CMakeLists.txt) and
# prints its contents and control fields.
#   bash scripts/package.sh            build the .deb
#   sudo dpkg -i build/carve_*.deb     install it: /usr/bin/carve and `man carve`
#   sudo dpkg -r carve                 remove it
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" --target carve
(cd build && cpack -G DEB >/dev/null)
deb=$(ls -t build/carve_*.deb | head -1)
dpkg-deb -I "$deb"
dpkg-deb -c "$deb"
echo "$deb"
