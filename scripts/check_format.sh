#!/usr/bin/env bash
# Fails if any C++ file of src/, tests/, bench/ or fuzz/ differs from .clang-format (run by
# scripts/test.sh). Fix with: clang-format -i FILE...
set -euo pipefail
cd "$(dirname "$0")/.."
format=$(command -v clang-format-14 || command -v clang-format)
mapfile -t files < <(git ls-files --cached --others --exclude-standard \
    'src/*.cpp' 'src/*.hpp' 'tests/*.cpp' 'tests/*.hpp' 'bench/*.cpp' 'bench/*.hpp' \
    'fuzz/*.cpp' 'fuzz/*.hpp')
"$format" --dry-run -Werror "${files[@]}"
echo "format: ${#files[@]} files as .clang-format says"
