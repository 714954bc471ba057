#!/bin/sh
# carve against CuraEngine lightning and PrusaSlicer grid on the shared models, every G-code
# measured by `carve check --mesh --json`. All the work is in compare.py (see its docstring);
# arguments are passed through, e.g.
#   bench/compare.sh --models cat,fandisk --sets default
#   bench/compare.sh --reuse --carve ../wt-carve/build/carve
exec /usr/bin/python3 "$(dirname "$0")/compare.py" "$@"
