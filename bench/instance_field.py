"""A field of Stanford bunnies for the instances' benchmarks (docs/performance.md, "Instances"):
writes FOLDER/field_instanced.json (one prototype placed N x N times) and
FOLDER/field_copies.json (the same bunnies written out as meshes), to be traced side by side:

    /usr/bin/python3 bench/instance_field.py FOLDER [--side N] [--bunny PATH]
    build/svetlo bench FOLDER/field_instanced.json --accel bvh,embree --rays diffuse
    build/svetlo bench FOLDER/field_copies.json --accel bvh,embree --rays diffuse

The bunny is ../shared/data/bunny/bun_zipper.ply (69,451 triangles), scaled by 8, each turned
about y by a fixed pseudo-random angle, spaced 1.6 apart on a floor, seen from above one corner.
"""
import argparse
import json
import os
import random

parser = argparse.ArgumentParser()
parser.add_argument("folder")
parser.add_argument("--side", type=int, default=10, help="bunnies along each side")
parser.add_argument("--bunny", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                    "..", "..", "shared", "data", "bunny",
                                                    "bun_zipper.ply"))
args = parser.parse_args()
os.makedirs(args.folder, exist_ok=True)
bunny = os.path.relpath(os.path.abspath(args.bunny), os.path.abspath(args.folder))

rng = random.Random(1)
spacing = 1.6
half = 0.5 * spacing * (args.side - 1)
places = []
for i in range(args.side):
    for j in range(args.side):
        places.append({"scale": 8, "rotate": [rng.uniform(0, 360), 0, 1, 0],
                       "translate": [i * spacing - half, -0.3, j * spacing - half]})

extent = half + spacing
base = {
    "camera": {"position": [extent, 0.6 * extent + 1.5, extent], "look_at": [0, 0, 0], "fov": 50},
    "film": {"width": 640, "height": 400},
    "render": {"engine": "path", "spp": 4, "max_depth": 3},
    "materials": {"clay": {"type": "lambert", "albedo": [0.8, 0.6, 0.45]},
                  "floor": {"type": "lambert", "albedo": 0.5}},
    "lights": [{"type": "directional", "direction": [-0.4, -1, -0.6], "irradiance": [2, 2, 2]}],
}
floor = {"type": "quad", "corner": [-extent, -0.3, extent], "edge_u": [2 * extent, 0, 0],
         "edge_v": [0, 0, -2 * extent], "material": "floor"}
mesh = {"type": "mesh", "file": bunny, "smooth": True, "material": "clay"}

instanced = dict(base)
instanced["prototypes"] = {"bunny": {"objects": [mesh]}}
instanced["objects"] = [floor] + [{"type": "instance", "prototype": "bunny", "transform": t}
                                  for t in places]
copies = dict(base)
copies["objects"] = [floor] + [dict(mesh, transform=t) for t in places]
for name, scene in (("field_instanced.json", instanced), ("field_copies.json", copies)):
    with open(os.path.join(args.folder, name), "w") as f:
        json.dump(scene, f, indent=1)
