"""The "Mesh rays" table (docs/performance.md, "Real meshes: bvh beside Embree"): svetlo's
BVH and Embree on the same rays through real meshes, primary and diffuse, one and two threads,
each run's ratio taken side by side in one `svetlo bench` call.

    /usr/bin/python3 bench/mesh_rays.py SVETLO FOLDER [RUNS]

Writes into FOLDER the bumpy sphere (200 x 400 quads of r = 1 + 0.05 sin 7 theta cos 9 phi, seen
from (0, 0.5, 3.5) with a 45 degree field of view, as an OBJ and its scene) and measures it with
scenes/bunny.json and ../shared/data/gltf/FlightHelmet (the model alone) at 256 x 256.
"""
import json
import math
import os
import re
import subprocess
import sys

svetlo, folder = sys.argv[1:3]
runs = int(sys.argv[3]) if len(sys.argv) > 3 else 3
root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
os.makedirs(folder, exist_ok=True)

# The bumpy sphere: rows of latitude theta in [0, pi], columns of longitude phi in [0, 2 pi).
rows, cols = 200, 400
obj = os.path.join(folder, "bumpy_sphere.obj")
with open(obj, "w") as f:
    for i in range(rows + 1):
        theta = math.pi * i / rows
        for j in range(cols):
            phi = 2.0 * math.pi * j / cols
            r = 1.0 + 0.05 * math.sin(7.0 * theta) * math.cos(9.0 * phi)
            f.write("v %.7f %.7f %.7f\n" % (r * math.sin(theta) * math.cos(phi), r * math.cos(theta),
                                            r * math.sin(theta) * math.sin(phi)))
    for i in range(rows):
        for j in range(cols):
            a = i * cols + j + 1
            b = i * cols + (j + 1) % cols + 1
            c, d = a + cols, b + cols
            f.write("f %d %d %d\nf %d %d %d\n" % (a, c, d, a, d, b))
sphere = os.path.join(folder, "bumpy_sphere.json")
with open(sphere, "w") as f:
    json.dump({"camera": {"position": [0, 0.5, 3.5], "look_at": [0, 0, 0], "fov": 45},
               "film": {"width": 256, "height": 256},
               "materials": {"grey": {"type": "lambert", "albedo": 0.5}},
               "lights": [{"type": "point", "position": [2, 4, 3], "intensity": 10}],
               "objects": [{"type": "mesh", "file": "bumpy_sphere.obj", "material": "grey"}]}, f)

meshes = [("scenes/bunny.json", os.path.join(root, "scenes", "bunny.json")),
          ("bumpy sphere", sphere),
          ("FlightHelmet", os.path.join(root, "..", "shared", "data", "gltf", "FlightHelmet",
                                        "FlightHelmet.gltf"))]
print("| mesh | rays | threads | bvh Mrays/s | Embree Mrays/s | bvh / Embree |")
print("| --- | --- | --- | --- | --- | --- |")
for name, path in meshes:
    for rays in ("primary", "diffuse"):
        for threads in ("1", "2"):
            mine, theirs, ratios = [], [], []
            for _ in range(runs):
                out = subprocess.run([svetlo, "bench", path, "--accel", "bvh,embree", "--rays", rays,
                                      "-t", threads, "-W", "256", "-H", "256"],
                                     capture_output=True, text=True, check=True).stdout
                speed = dict(re.findall(r"accel=(\w+) .*?mrays_per_s=([\d.]+)", out))
                hits = set(re.findall(r"hits=(\d+)", out))
                assert len(hits) == 1, "the structures disagree: " + out
                mine.append(float(speed["bvh"]))
                theirs.append(float(speed["embree"]))
                ratios.append(mine[-1] / theirs[-1])
            print("| %s | %s | %s | %s | %s | **%s** |" % (
                name, rays, threads, ", ".join("%.2f" % x for x in mine),
                ", ".join("%.2f" % x for x in theirs), ", ".join("%.2f" % x for x in ratios)),
                flush=True)
