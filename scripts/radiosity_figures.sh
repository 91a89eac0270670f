#!/usr/bin/env bash
# The pictures of docs/radiosity.md, made again from the demo scenes.
# Usage: scripts/radiosity_figures.sh [SVETLO] (default build/svetlo). Writes
# docs/images/radiosity_*.png. The path tracer's Cornell box is docs/images/path_cornell.png.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
svetlo=${1:-$root/build/svetlo}
img=$root/docs/images
cornell=$root/scenes/cornell.json
size=(-W 400 -H 400 --spp 16 --engine radiosity)
# The defaults (progressive here, Gouraud display); its patch mesh.
"$svetlo" render "$cornell" "${size[@]}" -o "$img/radiosity_cornell.png" \
    --aov patches="$img/radiosity_patches.png"
"$svetlo" render "$cornell" "${size[@]}" --set render.radiosity.display=gather \
    --set render.light_samples=16 -o "$img/radiosity_gather.png"
# Progressive refinement stopped early, with and without the ambient term; and uniform
# elements (no adaptive subdivision) against adaptive ones.
for shots in 100; do
    "$svetlo" render "$cornell" "${size[@]}" --set render.radiosity.solver=progressive \
        --set render.radiosity.max_iterations=$shots --set render.radiosity.adaptive=0 \
        -o "$img/radiosity_progressive_$shots.png"
    "$svetlo" render "$cornell" "${size[@]}" --set render.radiosity.solver=progressive \
        --set render.radiosity.max_iterations=$shots --set render.radiosity.adaptive=0 \
        --set render.radiosity.ambient_term=false -o "$img/radiosity_progressive_${shots}_no_ambient.png"
done
"$svetlo" render "$cornell" "${size[@]}" --set render.radiosity.solver=progressive \
    --set render.radiosity.adaptive=0 --set render.radiosity.element_size=0.2 \
    -o "$img/radiosity_uniform.png" --aov patches="$img/radiosity_uniform_patches.png"
"$svetlo" render "$cornell" "${size[@]}" --set render.radiosity.solver=progressive \
    --set render.radiosity.element_size=0.2 \
    -o "$img/radiosity_adaptive.png" --aov patches="$img/radiosity_adaptive_patches.png"
