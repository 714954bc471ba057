#!/usr/bin/env bash
# Builds the Debian package build/carve_<version>_<arch>.deb (CPack, see CMakeLists.txt) and
# prints its control fields and contents.
#   bash scripts/package.sh            build the .deb
#   bash scripts/package.sh --check    also install it (as root), run /usr/bin/carve --version
#                                      and man carve, then remove it again
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

if [ "${1:-}" = "--check" ]; then
    [ "$(id -u)" = 0 ] || { echo "--check installs the package: run it as root" >&2; exit 2; }
    if dpkg -s carve >/dev/null 2>&1 || [ -e /usr/bin/carve ]; then
        echo "carve is already installed: not touching it" >&2
        exit 2
    fi
    dpkg -i "$deb"
    trap 'dpkg -r carve >/dev/null' EXIT
    /usr/bin/carve --version
    man -w carve
    MANWIDTH=80 man carve 2>&1 | head -5
    echo "package check passed"
fi
