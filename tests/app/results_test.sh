#!/usr/bin/env bash
# The commands that show, check and reproduce results (docs/compare.md, docs/provenance.md),
# driven as a user would: crops against the full render for every engine on 1 and 2 threads,
# assemble, reproduce bit for bit, info, diff's exit codes, compare's sheets, --mse-log,
# SIGINT, and one error line for each bad input. PFMs are read by tests/app/pfm_tool.py.
# Usage: results_test.sh SVETLO SCENES_DIR
set -u
svetlo=$1
scenes=$2
tool="python3 $(dirname "$0")/pfm_tool.py"
source "$(dirname "$0")/checks.sh"

cornell="$scenes/cornell.json"
size=(-W 40 -H 32)

# Crops: bit for bit the full render's pixels, every engine, one thread and two.
for engine in raster whitted path radiosity; do
    "$svetlo" render "$cornell" --engine $engine "${size[@]}" --spp 2 -t 2 -q -o "$work/full_$engine.pfm" ||
        fail "full $engine"
    for t in 1 2; do
        "$svetlo" render "$cornell" --engine $engine "${size[@]}" --spp 2 -t $t -q \
            --crop 7,29,3,21 -o "$work/crop_${engine}_$t.pfm" || fail "crop $engine -t $t"
        check "crop $engine -t $t equals the full render" \
            $tool crop-equal "$work/full_$engine.pfm" "$work/crop_${engine}_$t.pfm" 7 29 3 21
    done
done

# Four quadrants assembled are the full image, byte for byte.
parts=()
for q in "0,20,0,16" "20,40,0,16" "0,20,16,32" "20,40,16,32"; do
    "$svetlo" render "$cornell" --engine path "${size[@]}" --spp 2 -q --crop $q -o "$work/q_$q.pfm"
    parts+=("$work/q_$q.pfm")
done
check "assemble of four quadrants" "$svetlo" assemble "${parts[@]}" -o "$work/assembled.pfm"
check "assembled equals the full render" cmp "$work/assembled.pfm" "$work/full_path.pfm"
expect_error "assemble with a gap" "gap: pixel \(20, 16\)" 1 assemble "${parts[@]:0:3}" -o "$work/gap.pfm"
expect_error "assemble with an overlap" "overlaps" 1 assemble "${parts[@]}" "${parts[0]}" -o "$work/o.pfm"
expect_error "assemble of two renders" "another render" 1 assemble "${parts[0]}" "$work/crop_raster_1.pfm" -o "$work/o.pfm"

# Reproduce: bit for bit from the provenance, after the scene file has changed.
cat > "$work/scene.json" <<'JSON'
{
  "camera": {"position": [0, 1, 5], "look_at": [0, 1, 0], "fov": 40},
  "film": {"width": 48, "height": 32},
  "render": {"spp": 2, "light_samples": 2},
  "materials": {"white": {"type": "lambert", "albedo": 0.8},
                "red": {"type": "phong", "kd": [0.6, 0.1, 0.1], "ks": 0.3, "shininess": 40}},
  "lights": [{"type": "point", "position": [0, 4, 2], "intensity": [10, 10, 10]},
             {"type": "area", "corner": [-1, 3, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2], "radiance": 2}],
  "objects": [{"type": "sphere", "center": [0, 1, 0], "radius": 1, "material": "red"},
              {"type": "quad", "corner": [-3, 0, 3], "edge_u": [6, 0, 0], "edge_v": [0, 0, -6], "material": "white"}]
}
JSON
"$svetlo" render "$work/scene.json" --engine path "${size[@]}" --spp 3 --seed 7 \
    --set camera.fov=45 -q -o "$work/orig.pfm"
"$svetlo" render "$work/scene.json" --engine whitted "${size[@]}" -q -o "$work/orig.png" \
    --crop 5,30,0,20 --aov depth="$work/orig_depth.exr"
echo '{"broken": ' > "$work/scene.json"  # the file is gone; the image holds its scene
check "reproduce a PFM" "$svetlo" reproduce "$work/orig.pfm" -o "$work/again.pfm" -q
check "reproduce is bit for bit" cmp "$work/orig.pfm" "$work/again.pfm"
check "reproduce a cropped PNG" "$svetlo" reproduce "$work/orig.png" -o "$work/again.png" -q
check "its pixels are the same" "$svetlo" diff "$work/again.png" "$work/orig.png" --metric mae
check "reproduce on two threads" "$svetlo" reproduce "$work/orig.pfm" -o "$work/again2.pfm" -t 2 -q
check "two threads bit for bit" cmp "$work/orig.pfm" "$work/again2.pfm"
check "reproduce an EXR AOV" "$svetlo" reproduce "$work/orig_depth.exr" -o "$work/again_depth.exr" -q
check "the AOV again" "$svetlo" diff "$work/again_depth.exr" "$work/orig_depth.exr" --metric mae
printf 'P3\n1 1\n255\n0 0 0\n' > "$work/plain.ppm"
"$svetlo" render "$cornell" "${size[@]}" -q -o "$work/plain.png"
python3 - "$work/plain.png" "$work/stripped.png" <<'PY'
import struct, sys  # copies a PNG without its text chunks
data = open(sys.argv[1], "rb").read()
out, pos = data[:8], 8
while pos < len(data):
    n = struct.unpack(">I", data[pos:pos + 4])[0]
    if data[pos + 4:pos + 8] not in (b"iTXt", b"tEXt"):
        out += data[pos:pos + 12 + n]
    pos += 12 + n
open(sys.argv[2], "wb").write(out)
PY
expect_error "reproduce without provenance" "no provenance" 1 reproduce "$work/stripped.png" -o "$work/x.png"

# info IMAGE: the keys of docs/provenance.md.
"$svetlo" info "$work/orig.pfm" --json > "$work/info.json"
check "info --json has the documented keys" python3 -c "
import json, sys
p = json.load(open('$work/info.json'))
keys = ['version', 'commit', 'command', 'scene_file', 'scene_sha256', 'scene', 'engine', 'spp',
        'seed', 'threads', 'seconds', 'crop', 'full_resolution']
missing = [k for k in keys if k not in p]
assert not missing, missing
assert p['spp'] == 3 and p['seed'] == 7 and p['crop'] == [0, 40, 0, 32], p
assert p['full_resolution'] == [40, 32] and p['scene']['camera']['fov'] == 45, p
assert p['command'][1:3] == ['render', '$work/scene.json'], p['command']
"
check "info IMAGE prints the engine" grep -q path <("$svetlo" info "$work/orig.pfm")

# diff: Unix exit codes.
check "diff of an image with itself exits 0" "$svetlo" diff "$work/orig.pfm" "$work/orig.pfm"
"$svetlo" diff "$work/full_whitted.pfm" "$work/full_raster.pfm" --metric rmse > "$work/d.out"
[ $? -eq 1 ] && grep -Eq '^rmse [0-9.e-]+$' "$work/d.out" && pass || fail "diff of two images: $(cat "$work/d.out")"
rmse=$(cut -d' ' -f2 "$work/d.out")
check "diff within the tolerance exits 0" "$svetlo" diff "$work/full_whitted.pfm" "$work/full_raster.pfm" --metric rmse --tolerance 1
check "diff's rmse is independent" python3 -c "
import math, subprocess
mse = float(subprocess.check_output(['python3', '$(dirname "$0")/pfm_tool.py', 'rmse2', '$work/full_whitted.pfm', '$work/full_raster.pfm']))
assert abs(math.sqrt(mse) - $rmse) < 1e-6 * max(1, $rmse), (math.sqrt(mse), $rmse)"
check "diff writes an error image" "$svetlo" diff "$work/full_whitted.pfm" "$work/full_raster.pfm" --metric flip --tolerance 1 -o "$work/err.png"
check "the error image is a PNG" test "$(head -c 4 "$work/err.png" | tail -c 3)" = PNG
# ꟻLIP against a second implementation straight from the papers' 2D kernels, in numpy
# (tests/app/flip_reference.py): LDR on PNGs, HDR on PFMs.
"$svetlo" render "$cornell" --engine raster "${size[@]}" -q -o "$work/raster.png"
"$svetlo" render "$cornell" --engine path --spp 2 "${size[@]}" -q -o "$work/path.png"
for pair in "ldr $work/raster.png $work/path.png" "hdr $work/full_raster.pfm $work/full_path.pfm"; do
    set -- $pair
    ours=$("$svetlo" diff "$3" "$2" --metric flip | cut -d' ' -f2)
    theirs=$(/usr/bin/python3 "$(dirname "$0")/flip_reference.py" "$1" "$2" "$3")
    check "ꟻLIP $1 agrees with the papers' 2D kernels ($ours, $theirs)" /usr/bin/python3 -c "
assert abs($ours - $theirs) <= 1e-5 * max(1.0, $theirs), ($ours, $theirs)"
done
expect_error "diff of different sizes" "is 22 x 18 but" 2 diff "$work/crop_raster_1.pfm" "$work/full_raster.pfm"
expect_error "diff of a missing file" "diff: no such file" 2 diff "$work/nothing.pfm" "$work/full_raster.pfm"
expect_error "diff's unknown metric" "--metric: unknown metric" 2 diff "$work/orig.pfm" "$work/orig.pfm" --metric psnr

# Crops that cannot be.
expect_error "crop outside the film" "--crop: the window 0,41,0,10 leaves the 40 x 32 film" 1 render "$cornell" "${size[@]}" --crop 0,41,0,10 -o "$work/x.png"
expect_error "empty crop" "--crop: the window 5,5,0,10 is empty" 1 render "$cornell" "${size[@]}" --crop 5,5,0,10 -o "$work/x.png"
expect_error "crop of three numbers" "--crop: expected X0,X1,Y0,Y1" 1 render "$cornell" "${size[@]}" --crop 1,2,3 -o "$work/x.png"

# compare: the sheet, the metrics, the errors.
check "compare" "$svetlo" compare "$cornell" -T raster:render.shading=gouraud -T whitted -T path:render.spp=4 \
    -T radiosity --reference path:render.spp=16 "${size[@]}" -o "$work/sheet.html" --png "$work/sheet.png" \
    --json "$work/m.json" --curves -q
check "compare's JSON" python3 -c "
import json
m = json.load(open('$work/m.json'))
assert list(m) == ['scene', 'reference', 'techniques'], list(m)
assert [t['spec'] for t in m['techniques']] == ['raster:render.shading=gouraud', 'whitted', 'path:render.spp=4', 'radiosity']
# Each technique named as the lecture names it (the registry's technique_name), the column's
# title on the sheets.
assert [t['name'] for t in m['techniques']] == ['Gouraud shading, ray-traced shadows', 'Whitted ray tracing', 'path tracing', 'radiosity'], [t['name'] for t in m['techniques']]
for t in m['techniques']:
    assert set(['spec', 'engine', 'seconds', 'mae', 'rmse', 'relmse', 'flip']) <= set(t), t
    assert 0 < t['flip'] < 1 and t['rmse'] > 0 and t['mae'] <= t['rmse'], t
assert len(m['techniques'][2]['curve']) == 4, m['techniques'][2]
# Radiosity: its solver's snapshots, then the final image, whose error is the sheet's.
r = m['techniques'][3]['curve']
assert len(r) >= 4, r
assert all(a['seconds'] <= b['seconds'] for a, b in zip(r, r[1:])), r
assert r[-1]['rmse'] == m['techniques'][3]['rmse'] and r[0]['relmse'] > 2 * r[-1]['relmse'], r
"
check "the HTML sheet is whole and self-contained" python3 -c "
import html.parser
text = open('$work/sheet.html').read()
class P(html.parser.HTMLParser):
    def __init__(self):
        super().__init__(); self.stack = []; self.srcs = []
    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        for k in ('src', 'href'):
            if k in a: self.srcs.append(a[k])
        if tag not in ('img', 'br', 'meta', 'line', 'polyline'): self.stack.append(tag)
    def handle_endtag(self, tag):
        if tag in ('img', 'br', 'meta', 'line', 'polyline'): return
        assert self.stack and self.stack[-1] == tag, (self.stack[-3:], tag); self.stack.pop()
p = P(); p.feed(text)
assert not p.stack, p.stack
assert p.srcs and all(s.startswith('data:image/png;base64,') for s in p.srcs), p.srcs[:3]
for spec in ['raster:render.shading=gouraud', 'whitted', 'path:render.spp=4', 'radiosity']: assert spec in text, spec
assert '<svg' in text
# Every technique is seen on the plot: one marked last pass each, an engine of one pass too.
assert text.count('<circle') == 4, text.count('<circle')
"
check "the PNG sheet" test "$(head -c 4 "$work/sheet.png" | tail -c 3)" = PNG
# The names of the lecture's techniques, as the sheets title them.
check "compare names the techniques" "$svetlo" compare "$scenes/cornell_radiosity.json" -W 16 -H 12 \
    -T raster:render.shadows=volume:render.shadow_volume.count=zfail \
    -T raster:render.shadows=map:render.shadow_map.filter=pcss \
    -T raster:render.shading=flat:render.visibility=painter:render.shadows=none \
    -T path:render.guiding=true -T radiosity:render.radiosity.solver=gauss_seidel:render.radiosity.element_size=0.5 \
    --reference path:render.spp=4 --json "$work/names.json" -q
check "the techniques' names" python3 -c "
import json
names = [t['name'] for t in json.load(open('$work/names.json'))['techniques']]
assert names == ['shadow volume, z-fail', 'shadow map, PCSS', \"flat shading, painter's algorithm, no shadows\",
                 'path tracing, guided', 'radiosity, Gauss-Seidel'], names
"
expect_error "compare: unknown engine" "-T phong: engine 'phong' is not available" 1 compare "$cornell" -T phong --json "$work/x.json"
expect_error "compare: a film unlike the reference's" "-T whitted:film.width=41: its film is 41 x 32; the reference's is 40 x 32" 1 compare "$cornell" -T whitted:film.width=41 --reference "$work/full_whitted.pfm" "${size[@]}" --json "$work/x.json"
expect_error "compare: an unwritable JSON, before any render" "--json: cannot write" 1 compare "$cornell" -T whitted "${size[@]}" --json "$work/no/such/folder/m.json"
expect_error "compare: unknown key" "-T raster:render.shadow=map: render.shadow: unknown key" 1 compare "$cornell" -T raster:render.shadow=map --json "$work/x.json"
# compare with buffers: a SPEC's aov=NAME shows its buffer beside its image, the very
# buffer render --aov writes (the PNG's pixels, as the sheet inlines them).
shadows="$scenes/shadows.json"
check "compare with buffers" "$svetlo" compare "$shadows" "${size[@]}" --reference path:render.spp=4 \
    -T raster:render.shadows=map:aov=shadow_map -T path:render.spp=2:aov=path_depth:aov=depth \
    -o "$work/buffers.html" --json "$work/buffers.json" --png "$work/buffers.png" -q
"$svetlo" render "$shadows" "${size[@]}" -e raster --set render.shadows='"map"' -q -o "$work/x.pfm" \
    --aov shadow_map="$work/map.png"
check "compare's buffers in its JSON and HTML" python3 -c "
import base64, json
m = json.load(open('$work/buffers.json'))
assert [t.get('aovs') for t in m['techniques']] == [['shadow_map'], ['depth', 'path_depth']], m
text = open('$work/buffers.html').read()
for name in ('shadow_map', 'path_depth', 'depth'): assert 'alt=\"%s of ' % name in text, name
start = text.index('alt=\"shadow_map of ')
src = text[text.index('base64,', start) + 7 : text.index('\"', text.index('base64,', start))]
import zlib
def pixels(png):  # the IDAT stream, inflated: the pixels whatever the text chunks
    data, pos, out = png[8:], 0, b''
    while pos < len(data):
        n = int.from_bytes(data[pos:pos + 4], 'big'); kind = data[pos + 4:pos + 8]
        if kind == b'IDAT': out += data[pos + 8:pos + 8 + n]
        pos += 12 + n
    return zlib.decompress(out)
assert pixels(base64.b64decode(src)) == pixels(open('$work/map.png', 'rb').read())
"
expect_error "compare: a buffer its technique does not make" "-T raster:aov=planar: needs render.engine raster with render.shadows planar" 1 compare "$shadows" -T raster:aov=planar --json "$work/x.json"
expect_error "compare: an unknown buffer" "-T whitted:aov=albedos: unknown AOV 'albedos'" 1 compare "$shadows" -T whitted:aov=albedos --json "$work/x.json"

# --mse-log: a line a pass, its last MSE the final image's.
"$svetlo" render "$cornell" --engine path "${size[@]}" --spp 16 -q -o "$work/ref.pfm"
"$svetlo" render "$cornell" --engine path "${size[@]}" --spp 4 --seed 3 -q -o "$work/logged.pfm" \
    --mse-reference "$work/ref.pfm" --mse-log "$work/log.csv"
expect_error "mse-log of a render that fails leaves no log" "camera.aperture: the rasterizer draws through a pinhole" 1 render "$cornell" --engine raster --set camera.aperture=0.1 "${size[@]}" --mse-reference "$work/ref.pfm" --mse-log "$work/failed.csv" -o "$work/x.pfm"
check "no log after the failure" test ! -e "$work/failed.csv"
check "mse-log has a line a pass" test "$(head -1 "$work/log.csv"),$(wc -l < "$work/log.csv")" = "spp,seconds,mse,relmse,5"
mse2=$($tool rmse2 "$work/logged.pfm" "$work/ref.pfm")
check "mse-log's last MSE is the image's" python3 -c "
last = open('$work/log.csv').read().split()[-1].split(',')
assert last[0] == '4' and abs(float(last[2]) - $mse2) <= 1e-6 * $mse2, (last, $mse2)"

# SIGINT: the passes done are written, the provenance says so, exit 130.
"$svetlo" render "$cornell" --engine path -W 64 -H 64 --spp 100000 -q -o "$work/int.pfm" &
pid=$!
sleep 1.5
kill -INT $pid
wait $pid
rc=$?
check "SIGINT exits 130" test $rc -eq 130
check "SIGINT writes the passes done" python3 -c "
import json
p = json.load(open('$work/int.pfm.json'))
assert p['interrupted'] is True and 1 <= p['spp'] < 100000, p['spp']"

# serve: a target that is neither a scene nor a folder, one line.
expect_error "serve of nothing" "serve: is neither a scene file nor a folder" 1 serve "$work/nothing"

summary
