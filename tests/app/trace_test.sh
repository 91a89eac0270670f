#!/usr/bin/env bash
# svetlo trace and the debug AOVs (docs/trace.md), driven as a user would. The trace: for
# every engine, scenes that make each kind of ray, one thread and two, the trace's total
# against the pixel of `render --spp 1 --crop X,X+1,Y,Y+1`, its contributions against its
# total, and its OBJ, checked by tests/app/trace_check.py; a later sample the same on any
# thread count; one error line for each bad input. The debug AOVs bvh_cost, path_depth and
# planar against closed forms and against other engines' buffers (tests/app/pfm_tool.py).
# Usage: trace_test.sh SVETLO SCENES_DIR
set -u
svetlo=$1
scenes=$2
here=$(dirname "$0")
source "$here/checks.sh"

# trace_case NAME SCENE X Y ARGS...: trace and render of pixel (X, Y) on 1 and 2 threads.
trace_case() {
    local name=$1 scene=$2 x=$3 y=$4
    shift 4
    for threads in 1 2; do
        rm -f "$work/t.json" "$work/t.obj" "$work/t.pfm"
        if ! "$svetlo" trace "$scene" --pixel "$x,$y" --json "$work/t.json" --obj "$work/t.obj" \
            -t "$threads" "$@" > "$work/t.txt" 2>&1; then
            fail "$name -t $threads: trace: $(head -c 300 "$work/t.txt")"; continue
        fi
        if ! "$svetlo" render "$scene" --spp 1 --crop "$x,$((x + 1)),$y,$((y + 1))" -q \
            -t "$threads" -o "$work/t.pfm" "$@" 2> "$work/r.txt"; then
            fail "$name -t $threads: render: $(head -c 300 "$work/r.txt")"; continue
        fi
        check "$name -t $threads" python3 "$here/trace_check.py" "$work/t.json" "$work/t.pfm" \
            "$work/t.obj"
        grep -o '"kind": "[a-z]*"' "$work/t.json" >> "$work/kinds"
        if grep -q '"engine": "raster"' "$work/t.json"; then
            grep -o '"visibility": [0-9.]*' "$work/t.json" >> "$work/raster_values"
        fi
    done
}
: > "$work/kinds"
: > "$work/raster_values"

small=(-W 64 -H 40)
spheres="$scenes/spheres.json"
for pixel in "14 25" "19 24" "30 22" "40 28" "44 31" "52 20" "5 5"; do
    set -- $pixel
    trace_case "whitted spheres ($1, $2)" "$spheres" "$1" "$2" -e whitted "${small[@]}"
    trace_case "path spheres ($1, $2)" "$spheres" "$1" "$2" -e path "${small[@]}"
done
for pixel in "24 10" "12 30" "36 36" "30 20"; do
    set -- $pixel
    trace_case "path cornell ($1, $2)" "$scenes/cornell.json" "$1" "$2" -e path -W 48 -H 48
    trace_case "radiosity ($1, $2)" "$scenes/cornell_radiosity.json" "$1" "$2" -W 48 -H 48
done
trace_case "path caustics" "$scenes/caustics.json" 20 20 -W 40 -H 40
trace_case "radiosity background" "$scenes/cornell_radiosity.json" 0 0 -W 48 -H 48 \
    --set camera.position=[0,1,12]
for shadows in none planar volume map raytraced; do
    for pixel in "24 30" "30 26" "8 19" "28 17"; do
        set -- $pixel
        trace_case "raster $shadows ($1, $2)" "$scenes/shadows.json" "$1" "$2" -e raster \
            "${small[@]}" --set render.shadows="\"$shadows\""
    done
done
for shading in flat gouraud; do
    trace_case "raster $shading" "$scenes/shadows.json" 30 26 -e raster "${small[@]}" \
        --set render.shading="\"$shading\"" --set render.shadows="\"map\""
done
# Both sides of a shadow: a raster light seen and one hidden by its technique.
check "a raster light hidden" grep -q '"visibility": 0' "$work/raster_values"
check "a raster light seen" grep -q '"visibility": 1' "$work/raster_values"
for kind in camera reflect refract shadow bsdf light; do
    check "a $kind ray was traced" grep -q "\"$kind\"" "$work/kinds"
done

# A later sample: a path's pass K, the same on one thread and two; its contributions add up.
for threads in 1 2; do
    "$svetlo" trace "$scenes/cornell.json" -e path -W 48 -H 48 --pixel 24,30 --sample 5 \
        -t "$threads" --json "$work/s$threads.json" > /dev/null 2>&1
done
check "sample 5 on 1 and 2 threads" cmp "$work/s1.json" "$work/s2.json"
check "sample 5 adds up" python3 "$here/trace_check.py" "$work/s1.json" -
check "sample 5 is pass 5" grep -q '"sample": 5' "$work/s1.json"
check "the text tree" grep -q "^total " "$work/t.txt"

# Bad input: one line naming the flag.
cornell="$scenes/cornell.json"
expect_error "pixel outside" "--pixel: \(400, 0\) lies outside the 400 x 400 film" 1 \
    trace "$cornell" --pixel 400,0
expect_error "pixel malformed" "--pixel: expected X,Y" 1 trace "$cornell" --pixel 4
expect_error "pixel negative" "--pixel" 1 trace "$cornell" --pixel -1,3
expect_error "sample of one" "--sample: sample 1 of 1" 1 trace "$cornell" --pixel 4,4 --sample 1
expect_error "raster sample" "--sample" 1 trace "$cornell" -e raster --pixel 4,4 --sample 1 --spp 4
expect_error "json unwritable" "--json" 1 trace "$cornell" --pixel 4,4 --json /nonexistent/t.json
check "nothing written on error" test ! -e /nonexistent/t.json

# Debug AOVs. A sphere on a plane under a point light, direct light only.
tool="python3 $here/pfm_tool.py"
cat > "$work/debug.json" <<'JSON'
{
  "camera": {"position": [0, 2, 6], "look_at": [0, 0.5, 0], "fov": 50},
  "film": {"width": 48, "height": 32},
  "render": {"spp": 1, "max_depth": 0},
  "materials": {"white": {"type": "lambert", "albedo": 0.8}},
  "lights": [{"type": "point", "position": [1, 4, 2], "intensity": [10, 10, 10]}],
  "objects": [{"type": "sphere", "center": [0, 1, 0], "radius": 1, "material": "white"},
              {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "white"}]
}
JSON
debug="$work/debug.json"
# bvh_cost without a structure: no node, and both primitives (the sphere, the unbounded
# plane) for every camera ray; with the BVH, the bunny's rays visit from one node to many.
for engine in whitted path; do
    "$svetlo" render "$debug" -e "$engine" --set render.accel='"none"' -q -o "$work/x.pfm" \
        --aov bvh_cost="$work/cost.pfm"
    check "$engine bvh_cost nodes, none" test "$($tool values "$work/cost.pfm" 0)" = "0"
    check "$engine bvh_cost primitives, none" test "$($tool values "$work/cost.pfm" 1)" = "2"
    check "$engine bvh_cost sum, none" $tool channel-sum "$work/cost.pfm"
done
if bunny_mesh "$scenes" "bvh_cost on the bunny"; then
    "$svetlo" render "$scenes/bunny.json" -e whitted -W 64 -H 40 --spp 1 -q -o "$work/x.pfm" \
        --aov bvh_cost="$work/cost.pfm" --aov bvh_cost="$work/cost.png"
    check "bvh_cost sum, bvh" $tool channel-sum "$work/cost.pfm"
    # The fewest nodes: the root alone on the eight-wide tree, the root and a child on the
    # four-wide one (a processor without AVX2, or a build without SIMD).
    fewest=$($tool values "$work/cost.pfm" 0 | cut -d' ' -f1)
    check "bvh_cost from 1 node ($fewest)" test "$fewest" -ge 1 -a "$fewest" -le 2
    check "bvh_cost to many" test "$($tool values "$work/cost.pfm" 0 | wc -w)" -gt 10
    check "bvh_cost as a PNG" test -s "$work/cost.png"
fi
# path_depth: at max_depth 0 a path that meets a surface traces its one BSDF ray (for MIS),
# one that meets nothing none; deeper, more.
"$svetlo" render "$debug" -e path -q -o "$work/x.pfm" --aov path_depth="$work/depth.pfm"
check "path_depth at max_depth 0" test "$($tool values "$work/depth.pfm" 0)" = "0 1"
"$svetlo" render "$debug" -e path --set render.max_depth=3 -q -o "$work/x.pfm" \
    --aov path_depth="$work/depth.pfm"
check "path_depth at max_depth 3" test "$($tool values "$work/depth.pfm" 0 | wc -w)" -gt 2
# planar: the projected mask is the complement of light 0's visibility under the technique,
# and here (shadows fall on the plane only) of the ray-traced visibility too.
"$svetlo" render "$debug" -e raster --set render.shadows='"planar"' -q -o "$work/x.pfm" \
    --aov planar="$work/planar.pfm" --aov visibility="$work/vis.pfm"
"$svetlo" render "$debug" -e whitted -q -o "$work/x.pfm" --aov visibility="$work/vis_rt.pfm"
check "planar is 1 - visibility" \
    test "$($tool agree "$work/planar.pfm" "$work/vis.pfm" 0 complement)" = "1.000000"
check "planar is 1 - the ray-traced visibility" \
    test "$($tool agree "$work/planar.pfm" "$work/vis_rt.pfm" 0 complement)" = "1.000000"
check "planar has shadow" test "$($tool values "$work/planar.pfm" 0)" = "0 1"
# Each debug AOV where its engine or technique is not: one line naming it.
expect_error "planar without planar" "--aov planar: needs render.engine raster with render.shadows planar" 1 \
    render "$debug" -e raster -o "$work/x.pfm" --aov planar="$work/p.pfm"
expect_error "bvh_cost in raster" "--aov bvh_cost: needs render.engine whitted or path" 1 \
    render "$debug" -e raster -o "$work/x.pfm" --aov bvh_cost="$work/p.pfm"
expect_error "path_depth in whitted" "--aov path_depth: needs render.engine path" 1 \
    render "$debug" -e whitted -o "$work/x.pfm" --aov path_depth="$work/p.pfm"
expect_error "bvh_cost of a grid" "render.accel: the bvh_cost AOV needs render.accel bvh" 1 \
    render "$debug" -e whitted --set render.accel='"grid"' -o "$work/x.pfm" --aov bvh_cost="$work/p.pfm"
check "no image from a refused AOV" test ! -e "$work/p.pfm"

summary
