#!/bin/sh
# Baselines of PrusaSlicer and CuraEngine on the shared models, judged by carve's G-code analyser.
# All the work is in baselines.py (see its docstring); arguments are passed through, e.g.
#   bench/baselines.sh --models cat,fandisk --slicers prusa
exec /usr/bin/python3 "$(dirname "$0")/baselines.py" "$@"
