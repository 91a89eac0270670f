"""A glTF for the loading benchmark (docs/performance.md, "Loading a model"): a sphere of
2 x 300 x 300 = 180,000 triangles in ten parts, each with its own material of two 2048 x 2048
PNG textures (base colour and metallic-roughness): twenty textures, as the issue's goal names.

    /usr/bin/python3 bench/load_model.py FOLDER
    /usr/bin/time -v build/svetlo render FOLDER/load_model.gltf -o /tmp/first.png -t 2 \\
        --set render.engine=raster --set film.width=960 --set film.height=540 --set render.spp=1
"""
import json
import math
import os
import struct
import sys
import zlib

import numpy as np

folder = sys.argv[1]
os.makedirs(folder, exist_ok=True)
SIDE, N, PARTS = 2048, 300, 10


def png(path, rgb):
    """An 8-bit RGB PNG of the array rgb (H x W x 3, uint8)."""
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[y].tobytes() for y in range(h))

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


y, x = np.mgrid[0:SIDE, 0:SIDE].astype(np.float32) / SIDE
rng = np.random.default_rng(1)
images = []
for k in range(2 * PARTS):
    # Smooth bands and a little noise: compresses about as a photograph's texture does.
    base = 0.5 + 0.5 * np.sin(2 * math.pi * ((k + 1) * x + (k % 3 + 1) * y))
    noise = rng.random((SIDE, SIDE), dtype=np.float32) * 0.15
    channels = [base * 0.8 + noise, (1 - base) * 0.6 + noise, np.full_like(base, 0.3) + noise]
    rgb = (np.clip(np.stack(channels, -1), 0, 1) * 255).astype(np.uint8)
    name = "texture%02d.png" % k
    png(os.path.join(folder, name), rgb)
    images.append({"uri": name})

# The sphere: rows of latitude, split into PARTS bands of rows.
positions, uvs, normals = [], [], []
for i in range(N + 1):
    theta = math.pi * i / N
    for j in range(N + 1):
        phi = 2 * math.pi * j / N
        p = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
        positions += p
        normals += p
        uvs += (j / N, i / N)
buffer = bytearray(struct.pack("<%df" % len(positions), *positions))
buffer += struct.pack("<%df" % len(normals), *normals)
buffer += struct.pack("<%df" % len(uvs), *uvs)
count = (N + 1) * (N + 1)
views = [{"buffer": 0, "byteOffset": 0, "byteLength": 12 * count},
         {"buffer": 0, "byteOffset": 12 * count, "byteLength": 12 * count},
         {"buffer": 0, "byteOffset": 24 * count, "byteLength": 8 * count}]
accessors = [{"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3",
              "min": [-1, -1, -1], "max": [1, 1, 1]},
             {"bufferView": 1, "componentType": 5126, "count": count, "type": "VEC3"},
             {"bufferView": 2, "componentType": 5126, "count": count, "type": "VEC2"}]
primitives, materials = [], []
rows = N // PARTS
for part in range(PARTS):
    indices = []
    for i in range(part * rows, (part + 1) * rows):
        for j in range(N):
            a, b = i * (N + 1) + j, (i + 1) * (N + 1) + j
            indices += (a, b, b + 1, a, b + 1, a + 1)
    offset = len(buffer)
    buffer += struct.pack("<%dI" % len(indices), *indices)
    views.append({"buffer": 0, "byteOffset": offset, "byteLength": 4 * len(indices)})
    accessors.append({"bufferView": len(views) - 1, "componentType": 5125,
                      "count": len(indices), "type": "SCALAR"})
    primitives.append({"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                       "indices": len(accessors) - 1, "material": part})
    materials.append({"pbrMetallicRoughness": {"baseColorTexture": {"index": 2 * part},
                                               "metallicRoughnessTexture": {"index": 2 * part + 1}}})
with open(os.path.join(folder, "load_model.bin"), "wb") as f:
    f.write(buffer)
gltf = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}], "meshes": [{"primitives": primitives}], "materials": materials,
        "textures": [{"source": k} for k in range(2 * PARTS)], "images": images,
        "buffers": [{"uri": "load_model.bin", "byteLength": len(buffer)}],
        "bufferViews": views, "accessors": accessors}
with open(os.path.join(folder, "load_model.gltf"), "w") as f:
    json.dump(gltf, f)
