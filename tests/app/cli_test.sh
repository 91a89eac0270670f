#!/usr/bin/env bash
# Drives the svetlo binary as a user would: every bad input gets one line
# `svetlo: error: FILE: WHERE: WHAT`, a non-zero exit and no output (an existing file is left
# untouched); good runs write what they say; output is the same whatever the thread count.
# Usage: cli_test.sh SVETLO TEST_DATA_DIR
set -u
svetlo=$1
data=$2
# The scratch folder and counts of checks.sh; this test's own expect_error, below, also wants
# no output left behind.
source "$(dirname "$0")/checks.sh"

cat > "$work/good.json" <<'JSON'
{
  "camera": {"position": [0, 1, 5], "look_at": [0, 1, 0], "fov": 40},
  "film": {"width": 48, "height": 32},
  "render": {"spp": 2, "light_samples": 2},
  "materials": {"white": {"type": "lambert", "albedo": 0.8}},
  "lights": [{"type": "point", "position": [0, 4, 2], "intensity": [10, 10, 10]},
             {"type": "area", "corner": [-1, 3, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2], "radiance": 2}],
  "objects": [{"type": "sphere", "center": [0, 1, 0], "radius": 1, "material": "white"},
              {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "white"}]
}
JSON

# expect_error NAME WHERE_PATTERN ARGS...: runs svetlo ARGS with -o $work/keep.png already
# holding "keep"; wants exit != 0, one stderr line naming WHERE, and keep.png unchanged.
expect_error() {
    local name=$1 where=$2
    shift 2
    echo keep > "$work/keep.png"
    "$svetlo" "$@" > "$work/stdout" 2> "$work/stderr"
    local rc=$?
    local lines
    lines=$(wc -l < "$work/stderr")
    if [ $rc -eq 0 ]; then fail "$name: exit 0"; return; fi
    if [ "$lines" -ne 1 ]; then fail "$name: $lines lines on stderr: $(cat "$work/stderr")"; return; fi
    if ! grep -Eq "^svetlo: error: [^:]+: .*${where}" "$work/stderr"; then
        fail "$name: stderr '$(cat "$work/stderr")' does not name '$where'"; return
    fi
    if [ "$(cat "$work/keep.png")" != keep ]; then fail "$name: output was touched"; return; fi
    if ls "$work" | grep -q '\.tmp'; then fail "$name: left a temporary file"; return; fi
    pass
}

# scene_with JQ-LIKE: writes $work/bad.json from good.json through a python edit.
scene_with() {
    python3 - "$work/good.json" "$work/bad.json" "$1" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
exec(sys.argv[3])
open(sys.argv[2], "w").write(json.dumps(scene) if not isinstance(scene, str) else scene)
PY
}

render_bad() {  # render_bad NAME WHERE EDIT [extra args]
    local name=$1 where=$2 edit=$3
    shift 3
    scene_with "$edit"
    expect_error "$name" "$where" render "$work/bad.json" -o "$work/keep.png" "$@"
}

# --- good runs ---
if "$svetlo" render "$work/good.json" -o "$work/out.png" --quiet 2> "$work/stderr" &&
   [ -s "$work/out.png" ] && [ ! -s "$work/stderr" ]; then pass; else fail "good render"; fi
"$svetlo" --version | grep -q '^svetlo ' && pass || fail "--version"
"$svetlo" render "$work/good.json" -o "$work/t1.pfm" -t 1 -q --aov visibility="$work/v1.pfm" &&
"$svetlo" render "$work/good.json" -o "$work/t2.pfm" -t 2 -q --aov visibility="$work/v2.pfm" &&
cmp -s "$work/t1.pfm" "$work/t2.pfm" && cmp -s "$work/v1.pfm" "$work/v2.pfm" && pass || fail "threads 1 vs 2 differ"
[ "$(head -c 3 "$work/t1.pfm" | head -1)" = "PF" ] && pass || fail "PFM header"
"$svetlo" render "$work/good.json" -o "$work/o.exr" -q --aov depth="$work/d.exr" --aov normal="$work/n.png" \
    --aov albedo="$work/a.pfm" --set camera.fov=30 --set 'lights.0.intensity=[5,5,5]' -W 20 -H 10 &&
    [ -s "$work/o.exr" ] && [ -s "$work/d.exr" ] && [ -s "$work/n.png" ] && [ -s "$work/a.pfm" ] &&
    head -2 "$work/a.pfm" | tail -1 | grep -q '^20 10$' && pass || fail "exr, aovs, --set, -W -H"
"$svetlo" info "$work/good.json" | grep -q '^lights     2' && pass || fail "info"
"$svetlo" bench "$work/good.json" --accel none,bvh --rays diffuse -t 1 > "$work/bench" 2>/dev/null
if [ "$(grep -c '^accel=\(none\|bvh\) build_ms=[0-9.]* mrays_per_s=[0-9.]* hits=[0-9]*$' "$work/bench")" = 2 ] &&
   [ "$(sed 's/.*hits=//' "$work/bench" | sort -u | wc -l)" = 1 ]; then pass; else fail "bench: $(cat "$work/bench")"; fi

# Every structure built in: the same hits on the bench, the same image from the renderer.
"$svetlo" bench "$work/good.json" --rays primary -t 2 > "$work/bench_all" 2>/dev/null
[ "$(grep -c '^accel=' "$work/bench_all")" -ge 4 ] && [ "$(sed 's/.*hits=//' "$work/bench_all" | sort -u | wc -l)" = 1 ] &&
    pass || fail "bench all: $(cat "$work/bench_all")"
for accel in none grid octree bvh2 bvh4; do
    "$svetlo" render "$work/good.json" -o "$work/accel_$accel.pfm" -q --set render.accel=$accel &&
        cmp -s "$work/accel_$accel.pfm" "$work/t1.pfm" && pass || fail "render.accel=$accel changes the image"
done
# CSG and implicit objects render, identically on any thread count.
scene_with 'scene["objects"].append({"type": "csg", "op": "difference", "material": "white", "children": [
    {"type": "box", "min": [-2, 0, -2], "max": [-1, 1, -1]}, {"type": "sphere", "center": [-1.5, 1, -1.5], "radius": 0.4}]})
scene["objects"].append({"type": "implicit", "material": "white", "sdf": {"op": "union", "smooth": 0.2, "children": [
    {"op": "sphere", "center": [1.5, 0.5, 0], "radius": 0.4}, {"op": "torus", "center": [1.5, 0.2, 0], "major_radius": 0.5, "minor_radius": 0.1}]}})'
cp "$work/bad.json" "$work/solids.json"
"$svetlo" render "$work/solids.json" -o "$work/s1.pfm" -t 1 -q && "$svetlo" render "$work/solids.json" -o "$work/s2.pfm" -t 2 -q &&
    cmp -s "$work/s1.pfm" "$work/s2.pfm" && ! cmp -s "$work/s1.pfm" "$work/t1.pfm" && pass || fail "csg and implicit render"

# The rasterizer: every shading mode, MSAA, painter, wireframe; the same image on any thread count.
for mode in flat gouraud phong depth normal overdraw; do
    "$svetlo" render "$work/solids.json" --engine raster -o "$work/r_$mode.png" -q --set render.shading=$mode &&
        [ -s "$work/r_$mode.png" ] && pass || fail "raster shading $mode"
done
"$svetlo" render "$work/solids.json" --engine raster -o "$work/r1.pfm" -t 1 -q --spp 4 --set render.antialias=msaa \
    --set render.wireframe=wu --aov depth="$work/rd1.pfm" &&
"$svetlo" render "$work/solids.json" --engine raster -o "$work/r2.pfm" -t 2 -q --spp 4 --set render.antialias=msaa \
    --set render.wireframe=wu --aov depth="$work/rd2.pfm" &&
    cmp -s "$work/r1.pfm" "$work/r2.pfm" && cmp -s "$work/rd1.pfm" "$work/rd2.pfm" && pass || fail "raster threads 1 vs 2 differ"
"$svetlo" render "$work/solids.json" --engine raster -o "$work/rp.png" -q --set render.visibility=painter \
    --set render.cull=back --set render.wireframe=bresenham && pass || fail "raster painter"
"$svetlo" info "$work/good.json" --matrices | grep -q '^projection' && pass || fail "info --matrices"
# Every shadow technique, and the teaching AOVs (PNG and PFM).
for t in none raytraced map volume planar; do
    "$svetlo" render "$work/solids.json" --engine raster -o "$work/s_$t.png" -q --set render.shadows=$t \
        --aov visibility="$work/sv_$t.pfm" && [ -s "$work/s_$t.png" ] && pass || fail "raster shadows $t"
done
"$svetlo" render "$work/solids.json" --engine raster -o "$work/sm.png" -q --set render.shadows=map \
    --set render.shadow_map.resolution=64 --aov shadow_map="$work/map.png" --aov stencil="$work/st.png" \
    2> /dev/null && fail "stencil AOV without volumes" || pass
"$svetlo" render "$work/solids.json" --engine raster -o "$work/sm.png" -q --set render.shadows=map \
    --set render.shadow_map.resolution=64 --aov shadow_map="$work/map.png" &&
    [ -s "$work/map.png" ] && pass || fail "shadow_map AOV"
"$svetlo" render "$work/solids.json" --engine raster -o "$work/sv.png" -q --set render.shadows=volume \
    --aov stencil="$work/st.pfm" && [ -s "$work/st.pfm" ] && pass || fail "stencil AOV"

# --- bad command lines ---
"$svetlo" > /dev/null 2>&1 && fail "no subcommand" || pass
expect_error "unknown engine" "render.engine" render "$work/good.json" -o "$work/keep.png" --engine foo
# The scene file's own engine, checked by the same registry in every command.
scene_with 'scene["render"]["engine"] = "magic"'
magic="render.engine: engine 'magic' is not available in this version of svetlo \\(available: raster, whitted, path, radiosity\\)"
expect_error "render: the scene's unknown engine" "$magic" render "$work/bad.json" -o "$work/keep.png"
expect_error "info: the scene's unknown engine" "$magic" info "$work/bad.json"
# --- radiosity ---
"$svetlo" render "$work/good.json" --engine radiosity -o "$work/rad.png" -q -W 32 -H 32 \
    --set render.radiosity.tolerance=0.2 --set render.radiosity.adaptive=0 \
    --aov patches="$work/patches.png" --aov visibility="$work/rvis.pfm" && [ -s "$work/rad.png" ] \
    && [ -s "$work/patches.png" ] && [ -s "$work/rvis.pfm" ] && pass || fail "radiosity render"
"$svetlo" info "$work/good.json" --set render.engine=radiosity | grep -q "^patches .* elements" \
    && pass || fail "info reports the patch mesh"
expect_error "patch size 0" "render.radiosity.patch_size: must be > 0" render "$work/good.json" \
    -o "$work/keep.png" --engine radiosity --set render.radiosity.patch_size=0
expect_error "negative element size" "render.radiosity.element_size" render "$work/good.json" \
    -o "$work/keep.png" --engine radiosity --set render.radiosity.element_size=-1
expect_error "patch mesh too large" "render.radiosity.element_size: the patch mesh would have" \
    render "$work/good.json" -o "$work/keep.png" --engine radiosity --set render.radiosity.element_size=1e-5
expect_error "progressive past its form factors" \
    "render.radiosity.patch_size: progressive refinement would compute 198656 patches" \
    render "$work/good.json" -o "$work/keep.png" --engine radiosity \
    --set render.radiosity.solver=progressive --set render.radiosity.patch_size=0.05 \
    --set render.radiosity.element_size=0.05
expect_error "matrix too large" "render.radiosity.solver: the matrix solvers take at most" \
    render "$work/good.json" -o "$work/keep.png" --engine radiosity --set render.radiosity.solver=jacobi
expect_error "hierarchical with a hemicube" "render.radiosity.form_factors" render "$work/good.json" \
    -o "$work/keep.png" --engine radiosity --set render.radiosity.solver=hierarchical \
    --set render.radiosity.form_factors=hemicube
expect_error "patches AOV of another engine" "--aov patches: needs render.engine radiosity" \
    render "$work/good.json" -o "$work/keep.png" --engine whitted --aov patches="$work/p.png"
expect_error "bad --set" "--set" render "$work/good.json" -o "$work/keep.png" --set nokey
expect_error "--set into a number" "--set camera.fov.x" render "$work/good.json" -o "$work/keep.png" --set camera.fov.x=1
expect_error "non-finite --set" "camera.fov: must be a number" render "$work/good.json" -o "$work/keep.png" --set camera.fov=1e999
expect_error "unknown aov" "--aov" render "$work/good.json" -o "$work/keep.png" --aov shine="$work/s.png"
expect_error "shadow_map aov of whitted" "--aov shadow_map: needs render.engine raster" render "$work/good.json" -o "$work/keep.png" --aov shadow_map="$work/s.png"
expect_error "shadow map kernel 0" "render.shadow_map.kernel" render "$work/good.json" -o "$work/keep.png" --set render.shadow_map.kernel=0
expect_error "shadow map filter" "render.shadow_map.filter" render "$work/good.json" -o "$work/keep.png" --set render.shadow_map.filter=box
expect_error "shadow map too large" "render.shadow_map.resolution: the shadow maps would take" render "$work/good.json" -o "$work/keep.png" --engine raster --set render.shadows=map --set render.shadow_map.resolution=16384
expect_error "unwritable output" "-o" render "$work/good.json" -o "$work/no/such/dir/out.png"
expect_error "unknown extension" "-o" render "$work/good.json" -o "$work/out.jpg"
expect_error "missing scene" "file" render "$work/nothing.json" -o "$work/keep.png"
# Flags get the scene keys' treatment: one line naming the flag, its rule and the value.
expect_error "--spp 0" "--spp: must be >= 1 \(is 0\)" render "$work/good.json" -o "$work/keep.png" --spp 0
expect_error "--seed -1" "--seed: must be >= 0 \(is -1\)" render "$work/good.json" -o "$work/keep.png" --seed -1
expect_error "-t abc" "-t: must be a whole number \(is 'abc'\)" render "$work/good.json" -o "$work/keep.png" -t abc
expect_error "-W 0" "-W: must be >= 1 \(is 0\)" render "$work/good.json" -o "$work/keep.png" -W 0
expect_error "-H huge" "-H: must be <= 65536 \(is [0-9]{24}\.\.\.\)$" render "$work/good.json" -o "$work/keep.png" -H "$(printf '9%.0s' $(seq 309))"
expect_error "bench -t -1" "-t: must be >= 0" bench "$work/good.json" -t -1
expect_error "unknown flag" "command line: .*--bogus" render "$work/good.json" -o "$work/keep.png" --bogus
expect_error "no scene" "command line: .*scene" render
expect_error "aov over the image" "--aov depth: is also the image's file" render "$work/good.json" -o "$work/keep.png" --aov depth="$work/keep.png"
expect_error "two aovs, one file" "--aov normal: is also the file of --aov depth" render "$work/good.json" -o "$work/keep.png" --aov depth="$work/d.pfm" --aov normal="$work/d.pfm"
# More threads than cores run on the cores, silently with -q, and the summary says how many.
if "$svetlo" render "$work/good.json" -o "$work/t.png" -q -t 64 2> "$work/stderr" && [ ! -s "$work/stderr" ]; then
    pass
else
    fail "-t 64 -q printed: $(cat "$work/stderr")"
fi
"$svetlo" render "$work/good.json" -o "$work/t.png" -t 64 2> "$work/stderr"
cores=$(nproc)
if grep -q " $cores threads" "$work/stderr" && ! grep -qi "warning" "$work/stderr"; then
    pass
else
    fail "-t 64 summary: $(cat "$work/stderr")"
fi

# --- bad scenes ---
render_bad "malformed JSON" "line 1, column" 'scene = "{\"camera\": [1,,2]}"'
render_bad "empty file" "line 1, column" 'scene = ""'
render_bad "missing key" "camera.position: missing key" 'del scene["camera"]["position"]'
render_bad "wrong type" "film.width: must be a number" 'scene["film"]["width"] = "wide"'
render_bad "unknown material type" "materials.white.type: unknown value" 'scene["materials"]["white"]["type"] = "velvet"'
render_bad "unknown shape" "objects\[0\].type: unknown value" 'scene["objects"][0]["type"] = "teapot"'
render_bad "unknown light" "lights\[0\].type: unknown value" 'scene["lights"][0]["type"] = "laser"'
render_bad "missing material" "objects\[1\].material: unknown material" 'scene["objects"][1]["material"] = "gold"'
render_bad "negative radius" "objects\[0\].radius: must be > 0" 'scene["objects"][0]["radius"] = -1'
render_bad "zero radius" "objects\[0\].radius: must be > 0" 'scene["objects"][0]["radius"] = 0'
render_bad "non-finite" "line 1, column [0-9]+: malformed JSON: number overflow" 'scene = json.dumps(scene).replace("[0, 1, 0], \"radius\"", "[0, 1e999, 0], \"radius\"")'
render_bad "degenerate camera" "camera.look_at" 'scene["camera"]["look_at"] = scene["camera"]["position"]'
# Finite JSON numbers beyond a float's range name their key (they crashed the BVH, or made NaN).
render_bad "inline position past float range" "objects\[0\].positions\[1\]\[0\]: must be at most 3.4e38" \
    'scene["objects"][0] = {"type": "mesh", "positions": [[0, 0, 0], [3.5e38, 0, 0], [0, 1, 0]], "indices": [0, 1, 2], "material": "white"}'
render_bad "look_at past float range" "camera.look_at\[0\]: must be at most 3.4e38" 'scene["camera"]["look_at"] = [-1e39, 0, 0]'
render_bad "position past float range" "camera.position\[1\]: must be at most 3.4e38" 'scene["camera"]["position"] = [0, 1e39, 0]'
render_bad "area corner past float range" "lights\[1\].corner\[2\]: must be at most 3.4e38" 'scene["lights"][1]["corner"] = [0, 0, 1e39]'
# Huge but representable coordinates: a triangle 6e38 wide, whose float cross product
# overflows. No crash, and nothing that is not finite reaches an image or an AOV (a sample
# that is not finite would be dropped and counted in the summary).
scene_with 'scene["objects"].append({"type": "mesh", "positions": [[-3e38, 0, 0], [3e38, 0, 0], [0, 1, 0]], "indices": [0, 1, 2], "material": "white"}); scene["film"] = {"width": 96, "height": 64}; scene["materials"]["glass"] = {"type": "dielectric", "ior": 1.5}; scene["objects"][0]["material"] = "glass"'
for engine in whitted raster path radiosity; do
    "$svetlo" render "$work/bad.json" --engine $engine -o "$work/huge.pfm" --aov normal="$work/huge_n.pfm" \
        --aov depth="$work/huge_d.pfm" 2> "$work/stderr" || fail "huge coordinates, $engine: exit $?"
    if python3 - "$work/huge.pfm" "$work/huge_n.pfm" "$work/huge_d.pfm" <<'PY'
import math, struct, sys
for path in sys.argv[1:]:
    data = open(path, "rb").read()
    header_end = [i for i, b in enumerate(data) if b == 10][2] + 1
    values = struct.unpack("<%df" % ((len(data) - header_end) // 4), data[header_end:])
    if not all(math.isfinite(v) for v in values):
        sys.exit(1)
PY
    then pass; else fail "huge coordinates, $engine: a value that is not finite in the image"; fi
done
"$svetlo" bench "$work/bad.json" --rays diffuse > /dev/null 2>&1 && pass || fail "huge coordinates: bench exit $?"
scene_with 'scene["objects"][0]["center"] = [1e39, 1, 1]'
expect_error "info past float range" "objects\[0\].center\[0\]" info "$work/bad.json"
expect_error "bench past float range" "objects\[0\].center\[0\]" bench "$work/bad.json"
render_bad "film too large" "film: .*too large" 'scene["film"] = {"width": 65536, "height": 65536}'
render_bad "missing mesh file" "objects\[0\].file" 'scene["objects"][0] = {"type": "mesh", "file": "nothing.obj", "material": "white"}'
render_bad "unknown key" "objects\[0\].raduis: unknown key" 'scene["objects"][0]["raduis"] = 1'
render_bad "negative spp" "render.spp" 'scene["render"]["spp"] = -4'
for f in broken.ply lying_header.ply bad_index.obj broken.gltf not_a_mesh.txt; do
    cp "$data/$f" "$work/$f"
    render_bad "malformed mesh $f" "objects\[0\].file: cannot read mesh" \
        "scene['objects'][0] = {'type': 'mesh', 'file': '$f', 'material': 'white'}"
done
# Every accelerator gives the same image of the Cornell box, whose OBJ holds two faces twice.
models="$(dirname "$0")/../../scenes/models"
cp "$models/CornellBox-Original.obj" "$models/CornellBox-Original.mtl" "$work/"
scene_with 'scene["objects"] = [{"type": "mesh", "file": "CornellBox-Original.obj"}]; scene["lights"] = []; scene["camera"] = {"position": [0, 1, 3.5], "look_at": [0, 1, 0], "fov": 40}'
for accel in bvh bvh4 bvh2 grid octree embree; do
    "$svetlo" render "$work/bad.json" -o "$work/cornell_$accel.pfm" -q --set render.accel=$accel || fail "cornell $accel"
done
same=1
for accel in bvh4 bvh2 grid octree embree; do
    cmp -s "$work/cornell_bvh.pfm" "$work/cornell_$accel.pfm" || same=0
done
[ $same -eq 1 ] && pass || fail "the accelerators disagree on the Cornell box"
# A depth AOV as PNG with an infinite plane in view is not black.
"$svetlo" render "$work/good.json" -o "$work/d.png" -q -W 240 -H 160 --aov depth="$work/depth.png"
python3 - "$work/depth.png" <<'PY' && pass || fail "the depth PNG is black where the sphere is"
import sys, zlib, struct
data = open(sys.argv[1], "rb").read()
# PNG: concatenate IDAT, inflate, skip each row's filter byte; the centre row's mean.
pos, idat, w, h = 8, b"", 0, 0
while pos < len(data):
    n, kind = struct.unpack(">I4s", data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + n]
    if kind == b"IHDR": w, h = struct.unpack(">II", body[:8])
    if kind == b"IDAT": idat += body
    pos += 12 + n
raw, stride, prev, rows = zlib.decompress(idat), 3 * w, bytearray(3 * w), []
for j in range(h):  # undo each row's filter (PNG spec, section 9)
    f, line = raw[j * (stride + 1)], bytearray(raw[j * (stride + 1) + 1:(j + 1) * (stride + 1)])
    for i in range(stride):
        a = line[i - 3] if i >= 3 else 0
        b, c = prev[i], prev[i - 3] if i >= 3 else 0
        p = a + b - c
        pred = [0, a, b, (a + b) // 2, a if abs(p - a) <= min(abs(p - b), abs(p - c)) else b if abs(p - b) <= abs(p - c) else c][f]
        line[i] = (line[i] + pred) & 255
    rows.append(line)
    prev = line
centre = rows[h // 2][3 * (w // 2)]  # the sphere, 4 units away
sys.exit(0 if centre > 10 else 1)
PY
# Files that are not files: refused at once, saying what they are (they were read until
# memory ran out).
expect_error "scene is a device" "file: is not a regular file" render /dev/zero -o "$work/keep.png"
render_bad "mesh is a device" "objects\[0\].file: cannot read mesh '/dev/zero': is not a regular file" \
    'scene["objects"][0] = {"type": "mesh", "file": "/dev/zero", "material": "white"}'
printf 'mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$work/zero_mtl.obj"
render_bad "mtllib is a device" "mtllib '/dev/zero' is not a regular file" \
    'scene["objects"][0] = {"type": "mesh", "file": "zero_mtl.obj"}'
render_bad "texture is a device" "materials.white.albedo.texture: .*is not a regular file" \
    'scene["materials"]["white"]["albedo"] = {"texture": "/dev/zero"}'
render_bad "texture is a directory" "materials.white.albedo.texture: .*is a directory" \
    'scene["materials"]["white"]["albedo"] = {"texture": "."}'
python3 - "$data/triangle.gltf" "$work/no_uri.gltf" <<'PY'
import json, sys
g = json.load(open(sys.argv[1]))
g["buffers"][0]["uri"] = ""
json.dump(g, open(sys.argv[2], "w"))
PY
render_bad "glTF buffer without uri (one line)" "objects\[0\].file: cannot read mesh 'no_uri.gltf'" \
    'scene["objects"][0] = {"type": "mesh", "file": "no_uri.gltf"}'
# Values read from files are checked as the scene's own: nothing that is not a finite,
# non-negative colour reaches a pixel.
python3 - "$work" <<'PY'
import struct, sys
work = sys.argv[1]
for name, texel in (("nan", float("nan")), ("negative", -0.5)):
    pixels = [0.5] * 12
    pixels[4] = texel
    with open(f"{work}/{name}.pfm", "wb") as f:
        f.write(b"PF\n2 2\n-1.0\n" + struct.pack("<12f", *pixels))
for name, kd in (("huge", "1e39 0.5 0.5"), ("negative", "-1 0.5 0.5")):
    open(f"{work}/{name}.mtl", "w").write(f"newmtl m\nKd {kd}\n")
    open(f"{work}/{name}_kd.obj", "w").write(f"mtllib {name}.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n")
PY
# A texture whose texels would take more than 768 MiB (8-bit files stay 8-bit in memory: a
# 1 MB PNG of 16384 x 16384 took 3 GiB as float, per material) is refused from its header,
# before it is decoded, and a texture that several materials use is read once.
python3 - "$work/huge.png" <<'PY'
import struct, sys, zlib
def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
header = struct.pack(">IIBBBBB", 32768, 16384, 8, 0, 0, 0, 0)  # grey: stb would take it
open(sys.argv[1], "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header))
PY
render_bad "texture too large" "cannot read texture 'huge.png': .*32768 x 16384 texels, which need 1536 MiB in memory, more than the 768 MiB" \
    "scene['materials']['white']['albedo'] = {'texture': 'huge.png'}"
for t in nan negative; do
    render_bad "texture with $t texels" "materials.white.albedo.texture: cannot read texture '$t.pfm': texel \\(1, 1\\)" \
        "scene['materials']['white']['albedo'] = {'texture': '$t.pfm'}"
done
for m in huge negative; do
    render_bad "MTL Kd $m" "material 'm' Kd .*must be finite and >= 0" \
        "scene['objects'][0] = {'type': 'mesh', 'file': '${m}_kd.obj'}"
done
gltf_with() {  # gltf_with NAME EDIT: $work/NAME.gltf from triangle.gltf through a python edit
    python3 - "$data/triangle.gltf" "$work/$1.gltf" "$2" <<'PY'
import json, sys
g = json.load(open(sys.argv[1]))
exec(sys.argv[3])
json.dump(g, open(sys.argv[2], "w"))
PY
}
gltf_with base_color 'g["materials"] = [{"pbrMetallicRoughness": {"baseColorFactor": [-1, 2, 1e39, 1]}}]; g["meshes"][0]["primitives"][0]["material"] = 0'
gltf_with emission 'g["materials"] = [{"emissiveFactor": [1e39, 1, 1]}]; g["meshes"][0]["primitives"][0]["material"] = 0'
gltf_with light 'g["extensions"]["KHR_lights_punctual"]["lights"][0]["intensity"] = 1e39'
render_bad "glTF baseColorFactor" "baseColorFactor \\(-1, 2, 1e\\+39\\)" \
    'scene["objects"][0] = {"type": "mesh", "file": "base_color.gltf"}'
render_bad "glTF emissiveFactor" "emissiveFactor times emissiveStrength \\(1e\\+39" \
    'scene["objects"][0] = {"type": "mesh", "file": "emission.gltf"}'
render_bad "glTF light intensity" "light 0 color times intensity" \
    'scene["objects"][0] = {"type": "mesh", "file": "light.gltf", "material": "white"}'
render_bad "emissive plane" "objects\[1\]: an emissive plane" \
    'scene["materials"]["glow"] = {"type": "emissive", "radiance": 1}; scene["objects"][1]["material"] = "glow"'
expect_error "bench unknown accel" "--accel" bench "$work/good.json" --accel kd-tree
render_bad "unknown accel" "render.accel: unknown value" 'scene["render"]["accel"] = "kd-tree"'
render_bad "unknown visibility" "render.visibility: unknown value" 'scene["render"]["visibility"] = "magic"'
render_bad "tessellation too coarse" "render.tessellation" 'scene["render"]["tessellation"] = 2'
render_bad "tessellation too fine" "render.tessellation: the scene would make" \
    'scene["render"]["tessellation"] = 4096; scene["objects"] += [dict(scene["objects"][0]) for k in range(2)]' --engine raster
render_bad "csg of a quad" "objects\[2\].children\[0\].type: a CSG child must be a closed shape" \
    'scene["objects"].append({"type": "csg", "op": "union", "material": "white", "children": [{"type": "quad", "corner": [0, 0, 0], "edge_u": [1, 0, 0], "edge_v": [0, 1, 0]}]})'
render_bad "bad sdf op" "objects\[2\].sdf.op: unknown value" \
    'scene["objects"].append({"type": "implicit", "material": "white", "sdf": {"op": "blob"}})'
render_bad "negative sdf radius" "objects\[2\].sdf.children\[0\].radius: must be > 0" \
    'scene["objects"].append({"type": "implicit", "material": "white", "sdf": {"op": "union", "children": [{"op": "sphere", "center": [0, 0, 0], "radius": -1}]}})' 

# The path tracer: the same image on 1 and 2 threads (AOVs too); --time renders passes until
# its budget is spent and writes a valid image; --spp caps it.
"$svetlo" render "$work/good.json" --engine path -o "$work/p1.pfm" -t 1 -q --aov visibility="$work/pv1.pfm" &&
"$svetlo" render "$work/good.json" --engine path -o "$work/p2.pfm" -t 2 -q --aov visibility="$work/pv2.pfm" &&
cmp -s "$work/p1.pfm" "$work/p2.pfm" && cmp -s "$work/pv1.pfm" "$work/pv2.pfm" && pass || fail "path threads 1 vs 2 differ"
# good.json asks for 2 spp: the scene's spp does not cap --time, --spp does.
if [ "${SVETLO_EMULATED:-0}" = 1 ]; then
    echo "skip --time's pass count: under an emulator (qemu-user) time says nothing"
elif "$svetlo" render "$work/good.json" --engine path -o "$work/timed.pfm" --time 0.3 2> "$work/stderr" &&
   [ "$(head -c 2 "$work/timed.pfm")" = "PF" ] && grep -Eq "path 48x32, [0-9]+ spp" "$work/stderr" &&
   ! grep -Eq "path 48x32, [12] spp" "$work/stderr"; then pass; else fail "--time: $(cat "$work/stderr")"; fi
"$svetlo" render "$work/good.json" --engine path -o "$work/capped.pfm" --time 60 --spp 3 2> "$work/stderr" &&
    grep -q "path 48x32, 3 spp" "$work/stderr" && pass || fail "--time with --spp: $(cat "$work/stderr")"
expect_error "path film too large" "film: the path tracer's film of 8192 x 8192 pixels needs" render "$work/good.json" -o "$work/keep.png" --engine path -W 8192 -H 8192 --aov depth="$work/big_d.pfm" --aov normal="$work/big_n.pfm"
render_bad "thin lens in the rasterizer" "camera.aperture: the rasterizer draws through a pinhole" 'scene["camera"]["aperture"] = 0.1' --engine raster
render_bad "thin lens, orthographic" "camera.aperture: a thin lens needs a perspective camera" 'scene["camera"]["type"] = "orthographic"; scene["camera"]["aperture"] = 0.1'
expect_error "time of whitted" "--time: needs a progressive engine" render "$work/good.json" -o "$work/keep.png" --time 1
expect_error "time not a number" "--time: must be a number of seconds" render "$work/good.json" -o "$work/keep.png" --engine path --time abc
expect_error "time zero" "--time: must be > 0" render "$work/good.json" -o "$work/keep.png" --engine path --time 0
expect_error "a later sample of the rasterizer" "--sample: raster's trace is of the whole pixel" trace "$work/good.json" -e raster --spp 4 --pixel 1,1 --sample 1
render_bad "photon count" "render.photons.count" 'scene["render"]["photons"] = {"count": 0}' --engine path
render_bad "photon alpha" "render.photons.alpha: must lie in" 'scene["render"]["photons"] = {"alpha": 1}' --engine path
render_bad "unknown caustics" "render.caustics: unknown value" 'scene["render"]["caustics"] = "sometimes"' --engine path
render_bad "small abbe" "materials.glass.dispersion.abbe: must be 0" 'scene["materials"]["glass"] = {"type": "dielectric", "dispersion": {"abbe": 0.5}}'
render_bad "cauchy with ior" "materials.glass.dispersion.cauchy: gives the ior" 'scene["materials"]["glass"] = {"type": "dielectric", "ior": 1.5, "dispersion": {"cauchy": [1.5, 0.004]}}'

# Flat and Gouraud shading under a shadow technique with no light at all: the ambient term
# alone, as with no technique (per-light shading indexed an empty array of light terms; the
# sanitizer build saw it).
cat > "$work/dark.json" <<'JSON'
{"camera": {"position": [0, 1, 5], "look_at": [0, 0.5, 0], "fov": 40}, "film": {"width": 32, "height": 24},
 "render": {"engine": "raster", "ambient": [0.1, 0.1, 0.1]},
 "materials": {"w": {"type": "lambert", "albedo": 0.8}}, "lights": [],
 "objects": [{"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5, "material": "w"}]}
JSON
for shading in flat gouraud; do
    "$svetlo" render "$work/dark.json" --set render.shading="\"$shading\"" --set render.shadows='"none"' \
        -q -o "$work/dark_none.pfm"
    "$svetlo" render "$work/dark.json" --set render.shading="\"$shading\"" --set render.shadows='"map"' \
        -q -o "$work/dark_map.pfm" 2> "$work/dark.err"
    check "$shading, shadow map, no light: the ambient term alone" cmp "$work/dark_none.pfm" "$work/dark_map.pfm"
    check "$shading, shadow map, no light: nothing on stderr" test ! -s "$work/dark.err"
done

# Bad environments: one line naming environment.file, no output.
printf 'PF\n2 1\n-1\n' > "$work/nan.pfm"
python3 -c "import struct,sys; sys.stdout.buffer.write(struct.pack('<6f', 1, 1, 1, float('nan'), 1, 1))" >> "$work/nan.pfm"
printf 'PF\n2 1\n-1\n' > "$work/negative.pfm"
python3 -c "import struct,sys; sys.stdout.buffer.write(struct.pack('<6f', 1, -1e-5, 1, 2, 2, 2))" >> "$work/negative.pfm"
scene_with "scene['environment'] = {'file': 'negative.pfm'}"
"$svetlo" render "$work/bad.json" -W 8 -H 8 -q -o "$work/negative_env.pfm" &&
    python3 -c "
import sys; sys.path.insert(0, '$(dirname "$0")'); import pfm_tool
assert min(min(r) for r in pfm_tool.read('$work/negative_env.pfm')[2]) >= 0" &&
    pass || fail "an environment's small negative texels (lossy EXR) are made 0"
render_bad "an environment that is not there" "environment.file: cannot read environment" \
    "scene['environment'] = {'file': 'nowhere.hdr'}"
render_bad "an environment with a NaN texel" "environment.file: cannot read environment" \
    "scene['environment'] = {'file': 'nan.pfm'}"
render_bad "an environment in 8 bits" "environment.file: an environment is a linear image" \
    "scene['environment'] = {'file': 'out.png'}"
render_bad "an environment's unknown key" "environment.turn: unknown key" \
    "scene['environment'] = {'file': 'nan.pfm', 'turn': 3}"

# A model file alone is a scene (docs/scene-format.md, "A model alone"): framed, lit, in every
# engine; its provenance holds the scene made of it, and reproduces it bit for bit; info reads it.
for engine in raster whitted path radiosity; do
    "$svetlo" render "$data/tetra_part.obj" -e $engine -W 48 -H 36 --spp 2 -q -o "$work/model_$engine.pfm" ||
        fail "a model alone, $engine"
    check "a model alone, $engine: lit" python3 -c "
import sys; sys.path.insert(0, '$(dirname "$0")'); import pfm_tool
assert max(max(r) for r in pfm_tool.read('$work/model_$engine.pfm')[2]) > 0.05"
done
check "a model alone: its provenance's scene frames it" grep -q '"fov":40' "$work/model_path.pfm.json"
"$svetlo" reproduce "$work/model_path.pfm" -o "$work/model_again.pfm" -q
check "a model alone reproduces bit for bit" cmp "$work/model_path.pfm" "$work/model_again.pfm"
check "info of a model" sh -c "'$svetlo' info '$data/triangle.gltf' | grep -q '^lights *1'"
expect_error "a model that cannot be read" "file: cannot read model" render "$data/broken.gltf" -o "$work/keep.png"

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
