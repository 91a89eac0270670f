#!/usr/bin/env bash
# The pictures of docs/path.md, made again from the demo scenes.
# Usage: scripts/path_figures.sh [SVETLO] (default build/svetlo). Writes docs/images/path_*.png.
# The convergence plot against Cycles comes from bench/cycles/convergence.py (docs/path.md).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
svetlo=${1:-$root/build/svetlo}
img=$root/docs/images
cornell=$root/scenes/cornell.json
size=(-W 400 -H 400)
"$svetlo" render "$cornell" --engine path --spp 1024 --set render.max_depth=64 \
    --set render.light_samples=1 "${size[@]}" -o "$img/path_cornell.png"
"$svetlo" render "$cornell" --engine whitted "${size[@]}" -o "$img/path_cornell_whitted.png"
"$svetlo" render "$cornell" --engine raster --spp 16 "${size[@]}" -o "$img/path_cornell_raster.png"
"$svetlo" render "$root/scenes/caustics.json" --spp 256 -o "$img/path_caustics.png"
"$svetlo" render "$root/scenes/caustics.json" --spp 256 --set render.caustics=none -W 320 \
    -H 200 -o "$img/path_caustics_none.png"
"$svetlo" render "$root/scenes/prism.json" --spp 256 -o "$img/path_prism.png"
# The three ways of finding light, at the same 16 samples per pixel.
for mis in light bsdf power; do
    "$svetlo" render "$root/scenes/mis.json" --spp 16 -W 480 -H 300 --set render.mis=$mis \
        -o "$img/path_mis_$mis.png"
done
# The hard scenes (docs/path.md, "Path guiding" and "Hard scenes"), at their own film and spp.
"$svetlo" render "$root/scenes/door_ajar.json" -o "$img/door_ajar.png"
"$svetlo" render "$root/scenes/door_ajar.json" --set render.guiding=true -o "$img/door_ajar_guided.png"
"$svetlo" render "$root/scenes/lamp_shade.json" -o "$img/lamp_shade.png"
"$svetlo" render "$root/scenes/glass_caustic.json" -o "$img/glass_caustic.png"
