#!/usr/bin/env bash
# The modules' dependencies point one way (README, "Layout"):
#   core <- scene <- geometry <- shading <- {raster, rt} <- {pt, radiosity} <- job <- apps
# A module includes only its own headers and those of the modules below it; raster and rt
# never include each other.
set -euo pipefail
cd "$1/src/svetlo"
allowed() {
    case "$1" in
        core) echo "core" ;;
        scene) echo "core scene" ;;
        geometry) echo "core scene geometry" ;;
        shading) echo "core scene geometry shading" ;;
        raster) echo "core scene geometry shading raster" ;;
        rt) echo "core scene geometry shading rt" ;;
        pt) echo "core scene geometry shading rt pt" ;;
        radiosity) echo "core scene geometry shading raster rt radiosity" ;;
        job) echo "core scene geometry shading raster rt pt radiosity job" ;;
    esac
}
bad=0
for module in core scene geometry shading raster rt pt radiosity job; do
    ok=" $(allowed "$module") "
    while IFS= read -r line; do
        file=${line%%:*}
        used=$(echo "$line" | sed -E 's|.*#include "svetlo/([a-z]+)/.*|\1|')
        if [[ "$ok" != *" $used "* ]]; then
            echo "layering: $file includes svetlo/$used/ (a $module file may include: $(allowed "$module"))"
            bad=1
        fi
    done < <(grep -rn '#include "svetlo/' "$module" || true)
done
[ "$bad" -eq 0 ] && echo "layering: every include points down"
exit "$bad"
