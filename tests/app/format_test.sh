#!/usr/bin/env bash
# Every C++ source is clang-formatted (.clang-format: Google base, 4 spaces, 100 columns).
# `make format` fixes what this finds.
set -euo pipefail
cd "$1"
command -v clang-format > /dev/null || { echo "clang-format is missing (scripts/setup installs it)"; exit 1; }
files=$(find src apps python tests bench -name '*.cpp' -o -name '*.h' -o -name '*.inc' | sort)
clang-format --dry-run --Werror $files
echo "$(echo "$files" | wc -l) files formatted"
