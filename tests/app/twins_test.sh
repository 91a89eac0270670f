#!/usr/bin/env bash
# Every engine's images from a build with SIMD against a build of the scalar twins alone
# (SVETLO_SIMD=OFF, docs/reading.md): `make test-scalar` runs it after the scalar suite.
#   whitted, path, radiosity: the same bytes (every twin does the same arithmetic in the
#     same order: the BVH's box and triangle tests, its build, the sampler);
#   raster: within 1e-4 relative, as the fast path's shading against the general one
#     (simd_shading.h: exp2/log2 polynomials and refined reciprocals); the rasterization,
#     stencil counts and shadow-map lookups themselves are exact, which the engine's own
#     images with Gouraud shading (no fast path) show byte for byte, but for the PCF
#     filter's four-wide row sum (another order of the same sum).
# Usage: twins_test.sh SIMD_SVETLO SCALAR_SVETLO SCENES_DIR
set -uo pipefail
simd=$1
svetlo=$2  # checks.sh's expect_error runs $svetlo
scenes=$3
tool="/usr/bin/python3 $(dirname "$0")/pfm_tool.py"
source "$(dirname "$0")/checks.sh"

render_both() {  # NAME SCENE ARGS...: the two images, $work/NAME.simd.pfm and .scalar.pfm
    local name=$1 scene=$2
    shift 2
    "$simd" render "$scenes/$scene" -W 160 -H 120 -q -o "$work/$name.simd.pfm" "$@" &&
        "$svetlo" render "$scenes/$scene" -W 160 -H 120 -q -o "$work/$name.scalar.pfm" "$@"
}
same() {  # NAME SCENE ARGS...
    local name=$1
    if render_both "$@"; then
        check "$name: the same bytes" cmp "$work/$name.simd.pfm" "$work/$name.scalar.pfm"
    else
        fail "$name: render failed"
    fi
}
close() {  # NAME TOLERANCE SCENE ARGS...
    local name=$1 tolerance=$2
    shift 2
    if render_both "$name" "$@"; then
        local worst
        worst=$($tool worst-relative "$work/$name.simd.pfm" "$work/$name.scalar.pfm" 1e-3)
        check "$name: within $tolerance ($worst)" /usr/bin/python3 -c "assert $worst <= $tolerance"
    else
        fail "$name: render failed"
    fi
}

with_meshes="cornell.json spheres.json solids.json"
bunny_mesh "$scenes" bunny.json && with_meshes="$with_meshes bunny.json"
for scene in $with_meshes; do
    same "whitted ${scene%.json}" "$scene" -e whitted
    same "path ${scene%.json}" "$scene" -e path --spp 4
    same "whitted ${scene%.json}, 1 thread" "$scene" -e whitted -t 1
done
same "path caustics" caustics.json -e path --spp 4
same "radiosity" cornell_radiosity.json
for shadows in map volume planar raytraced; do
    close "raster phong, $shadows" 1e-4 shadows.json -e raster --set render.shadows="\"$shadows\""
done
for shadows in volume planar raytraced; do
    same "raster gouraud, $shadows" shadows.json -e raster --set render.shadows="\"$shadows\"" \
        --set render.shading='"gouraud"'
done
same "raster gouraud, map none" shadows.json -e raster --set render.shading='"gouraud"' \
    --set render.shadow_map.filter='"none"'
# PCF (and PCSS, which filters with it) with a kernel of at most 3 texels sums a row four-wide.
for filter in pcf pcss; do
    for kernel in 3 5; do
        close "raster gouraud, map $filter $kernel" 1e-5 shadows.json -e raster \
            --set render.shading='"gouraud"' --set render.shadow_map.filter="\"$filter\"" \
            --set render.shadow_map.kernel=$kernel
    done
done
close "raster 4 spp" 1e-4 raster.json -e raster --spp 4
summary
