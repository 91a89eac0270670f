#!/usr/bin/env bash
# The pictures of the engines' pages that are single renders (docs/raster.md, whitted.md,
# radiosity.md, path.md): each page's caption gives the same command. Run by scripts/figures.sh.
# Usage: scripts/page_figures.sh [SVETLO]   (default build/svetlo)
set -euo pipefail
cd "$(dirname "$0")/.."
svetlo=${1:-build/svetlo}
out=docs/images
r() { echo "svetlo render $*" >&2; "$svetlo" render "$@" -q; }

# The demo scenes as they are (README.md, docs/geometry.md, docs/whitted.md).
for scene in spheres solids materials cornell bunny; do
    r scenes/$scene.json -o $out/$scene.png
done
# docs/raster.md: the shading modes, the painter's algorithm, the texture filters.
raster=scenes/raster.json
r $raster --set render.shading='"flat"' --set render.tessellation=16 -o $out/raster_flat.png
r $raster --set render.shading='"gouraud"' --set render.tessellation=16 \
    --set render.wireframe='"wu"' -o $out/raster_gouraud.png
r $raster --set render.shading='"depth"' -o $out/raster_depth.png
r $raster --set render.shading='"normal"' -o $out/raster_normal.png
r $raster --set render.shading='"overdraw"' -o $out/raster_overdraw.png
r $raster -o $out/raster_phong.png
r $raster -e whitted -o $out/raster_whitted.png
r $raster --set render.visibility='"painter"' -o $out/raster_painter.png
for filter in bilinear trilinear anisotropic; do
    r $raster --spp 1 --set materials.floor.albedo.filter="\"$filter\"" -o $out/raster_$filter.png
done
# docs/whitted.md: the AOVs.
r scenes/spheres.json -o /tmp/svetlo_spheres.png --aov depth=$out/spheres_depth.png \
    --aov normal=$out/spheres_normal.png --aov visibility=$out/spheres_visibility.png
# docs/radiosity.md: 100 shots of the progressive solver, with and without the ambient term.
for ambient in true false; do
    name=radiosity_progressive_100$([ $ambient = false ] && echo _no_ambient || true)
    r scenes/cornell_radiosity.json -W 400 -H 400 --set render.radiosity.solver='"progressive"' \
        --set render.radiosity.max_iterations=100 --set render.radiosity.ambient_term=$ambient \
        -o $out/$name.png
done
# docs/path.md: depth of field, focused on the mirror sphere.
r scenes/spheres.json -e path -W 480 -H 300 --spp 64 --set camera.aperture=0.3 \
    --set camera.focus_distance=6.86 -o $out/path_depth_of_field.png
