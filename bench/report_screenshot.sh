#!/bin/sh
# Slices a real model with --report and takes a headless Chromium screenshot of the HTML page
# (docs/report.png by default), then checks that the page's script ran without a console error.
# Needs chromium (apt-get install -y chromium); the test suite does not.
#
#   bench/report_screenshot.sh [MODEL] [OUT.png]     (CARVE=path/to/carve to pick a binary)
set -eu

ROOT=$(cd "$(dirname "$0")/.." && pwd)
CARVE=${CARVE:-$ROOT/build/carve}
MODEL=${1:-$ROOT/../shared/models/fandisk.stl}
OUT=${2:-$ROOT/docs/report.png}
SIZE=${SIZE:-1400,1000}

command -v chromium >/dev/null 2>&1 || { echo "chromium not found: apt-get install -y chromium" >&2; exit 2; }
[ -x "$CARVE" ] || { echo "no carve binary at $CARVE (set CARVE=...)" >&2; exit 2; }

TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT INT TERM

"$CARVE" slice "$MODEL" -o "$TMP/model.gcode" --report "$TMP/report.html"

# No network, no profile, no background services: the page must stand on its own.
browser() {
    chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
        --disable-background-networking --disable-component-update --disable-sync \
        --user-data-dir="$TMP/profile" "$@"
}

browser --screenshot="$OUT" --window-size="$SIZE" "file://$TMP/report.html" 2>/dev/null
browser --enable-logging=stderr --v=0 --dump-dom "file://$TMP/report.html" \
    >"$TMP/dom.html" 2>"$TMP/console.log" || true

status=0
if grep -q "CONSOLE" "$TMP/console.log"; then
    echo "console messages from the report page:" >&2
    grep "CONSOLE" "$TMP/console.log" >&2
    status=1
fi
# The script fills in the layer title; "Layer" alone means it did not run.
if ! grep -q 'id="lnum">Layer [0-9]' "$TMP/dom.html"; then
    echo "the report's script did not run (layer title not filled in)" >&2
    status=1
fi
echo "report $(wc -c <"$TMP/report.html") bytes, screenshot $OUT"
exit $status
