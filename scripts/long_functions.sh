#!/usr/bin/env bash
# Functions of src/ and apps/ longer than N lines (default 80), longest first, as Universal
# Ctags measures them (from the line of the name to the closing brace). Issue 51's measure:
# none over 100 but the two SIMD kernels, at most ten over 80 (docs/reading.md).
# Usage: scripts/long_functions.sh [N]
set -eu
limit=${1:-80}
cd "$(dirname "$0")/.."
ctags -R --fields=+ne --c++-kinds=f --output-format=u-ctags -f - src apps |
    awk -F'\t' -v limit="$limit" '{
        line = ""; end = ""
        for (i = 4; i <= NF; i++) {
            if ($i ~ /^line:/) line = substr($i, 6)
            if ($i ~ /^end:/) end = substr($i, 5)
        }
        if (line != "" && end != "" && end - line + 1 > limit) print end - line + 1, $2, $1
    }' | sort -rn
