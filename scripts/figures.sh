#!/usr/bin/env bash
# make figures: regenerates the pictures of docs/ from fixed seeds (docs/techniques.md says
# which command made each). The technique sheets come first; the engines' own pages follow
# through their scripts (scripts/radiosity_figures.sh, scripts/shadow_figures.py,
# scripts/path_figures.sh). The Cycles convergence plots need Blender: bench/cycles/
# convergence.py (docs/path.md) makes them, not this script.
# Usage: scripts/figures.sh [SVETLO]   (default build/svetlo)
set -euo pipefail
cd "$(dirname "$0")/.."
svetlo=${1:-build/svetlo}
out=docs/images
mkdir -p "$out"

sheet() {  # sheet NAME SCENE ARGS...: docs/images/sheet_NAME.png and its metrics
    local name=$1 scene=$2
    shift 2
    echo "svetlo compare $scene $* --png $out/sheet_$name.png --json $out/sheet_$name.json" >&2
    "$svetlo" compare "$scene" "$@" --seed 1 --png "$out/sheet_$name.png" \
        --json "$out/sheet_$name.json" -q
}

# Shading and shadows against direct light alone (no ambient term; a black background, so no
# environment light for the path tracer; paths that end at their first hit: max_depth 0), so
# that the sheets show what the technique changes and not the missing indirect light.
direct=(--set render.ambient=0 --set render.background=0 --reference path:render.spp=1024:render.max_depth=0)
sheet shading scenes/raster.json -W 320 -H 200 "${direct[@]}" \
    -T raster:render.shading=flat -T raster:render.shading=gouraud -T raster:render.shading=phong
sheet lighting scenes/materials.json -W 400 -H 150 \
    -T raster -T whitted -T path:render.spp=16
sheet shadows scenes/shadows.json -W 240 -H 150 "${direct[@]}" \
    -T raster:render.shadows=planar \
    -T raster:render.shadows=volume:render.shadow_volume.count=zpass \
    -T raster:render.shadows=volume:render.shadow_volume.count=zfail \
    -T raster:render.shadows=map:render.shadow_map.filter=none \
    -T raster:render.shadows=map:render.shadow_map.filter=pcf \
    -T raster:render.shadows=map:render.shadow_map.filter=pcss \
    -T raster:render.shadows=raytraced
sheet global scenes/cornell.json -W 160 -H 160 --curves \
    -T whitted -T path:render.spp=64 -T radiosity

# The ray tracers' debug AOVs (docs/trace.md).
"$svetlo" render scenes/bunny.json -e whitted --spp 1 --aov bvh_cost=$out/bvh_cost.png \
    -o /tmp/svetlo_bunny.png -q
"$svetlo" render scenes/cornell.json -e path --spp 16 -W 256 -H 256 \
    --aov path_depth=$out/path_depth.png -o /tmp/svetlo_cornell.png -q

# The teaching pages: two projections (docs/cameras.md), three exposures (docs/radiometry.md).
"$svetlo" render scenes/solids.json -e raster -W 320 -H 200 -o $out/camera_perspective.png -q
"$svetlo" render scenes/solids.json -e raster -W 320 -H 200 -o $out/camera_orthographic.png -q \
    --set camera.type='"orthographic"' --set camera.height=4.5
for e in 0.5 1 2; do
    "$svetlo" render scenes/spheres.json -W 320 -H 200 --set render.exposure=$e \
        -o $out/exposure_$e.png -q
done

# The viewer, screenshotted by its browser test in headless chromium (docs/viewer.md).
/usr/bin/python3 tests/app/viewer_test.py "$svetlo" scenes $out/viewer.png > /dev/null

if [ "${SVETLO_FIGURES_SHEETS_ONLY:-0}" = 1 ]; then exit 0; fi
scripts/page_figures.sh "$svetlo"
scripts/radiosity_figures.sh "$svetlo"
python3 scripts/shadow_figures.py "$svetlo"
scripts/path_figures.sh "$svetlo"
