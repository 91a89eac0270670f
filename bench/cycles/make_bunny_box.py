"""Writes the path tracer's mesh benchmark scene for the Cycles comparison (numpy only).

Two Stanford bunnies (69,451 triangles each) in a box lit by an emissive ceiling panel, all
diffuse, as one OBJ with its MTL and a svetlo scene that loads it: a scene that both svetlo and
the Cycles harness in ../shared/anchors/cycles render the same way (OBJ meshes with Lambert
and emissive MTL materials, no transforms). The bunnies' transform is baked into the OBJ.

    /usr/bin/python3 bench/cycles/make_bunny_box.py ../shared/data/bunny/bun_zipper.ply OUT_DIR

writes OUT_DIR/bunny_box.obj, .mtl and .json (139,000 triangles)."""
import json
import os
import sys

import numpy as np


def read_ply_ascii(path):
    """(vertices N x 3, triangles M x 3) of an ASCII PLY whose faces are triangles."""
    lines = open(path).read().splitlines()
    n_vertex = n_face = 0
    end = 0
    for k, line in enumerate(lines):
        x = line.split()
        if x[:2] == ["element", "vertex"]:
            n_vertex = int(x[2])
        elif x[:2] == ["element", "face"]:
            n_face = int(x[2])
        elif x and x[0] == "end_header":
            end = k + 1
            break
    v = np.array([l.split()[:3] for l in lines[end:end + n_vertex]], dtype=np.float64)
    f = np.array([l.split()[1:4] for l in lines[end + n_vertex:end + n_vertex + n_face]],
                 dtype=np.int64)
    return v, f


def rotation_y(degrees):
    a = np.radians(degrees)
    return np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])


def main():
    ply, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    v, f = read_ply_ascii(ply)
    # Two bunnies: scale 8 (about 1.2 m tall), turned and set on the floor (y = 0).
    bunnies = [(8.0, 25.0, np.array([-0.7, 0.0, 0.1])), (8.0, -35.0, np.array([0.75, 0.0, -0.4]))]
    with open(os.path.join(out, "bunny_box.mtl"), "w") as m:
        m.write("newmtl white\nKd 0.75 0.75 0.75\n"
                "newmtl red\nKd 0.63 0.065 0.05\n"
                "newmtl green\nKd 0.14 0.45 0.091\n"
                "newmtl clay\nKd 0.8 0.6 0.45\n"
                "newmtl light\nKd 0.78 0.78 0.78\nKe 17 12 4\n")
    with open(os.path.join(out, "bunny_box.obj"), "w") as o:
        o.write("mtllib bunny_box.mtl\n")
        base = 1
        for scale, turn, at in bunnies:
            p = (v * scale) @ rotation_y(turn).T
            p += at - np.array([0.0, p[:, 1].min(), 0.0])
            o.write("usemtl clay\n")
            o.write("".join(f"v {x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in p))
            o.write("".join(f"f {a + base} {b + base} {c + base}\n" for a, b, c in f))
            base += len(p)
        # The box [-2, 2] x [0, 3] x [-2, 2], open toward the camera (+z); faces wound so that
        # their counter-clockwise side looks inward.
        quads = [("white", [(-2, 0, -2), (-2, 0, 2), (2, 0, 2), (2, 0, -2)]),   # floor
                 ("white", [(-2, 3, -2), (2, 3, -2), (2, 3, 2), (-2, 3, 2)]),   # ceiling
                 ("white", [(-2, 0, -2), (2, 0, -2), (2, 3, -2), (-2, 3, -2)]),  # back
                 ("red", [(-2, 0, -2), (-2, 3, -2), (-2, 3, 2), (-2, 0, 2)]),    # left
                 ("green", [(2, 0, -2), (2, 0, 2), (2, 3, 2), (2, 3, -2)]),      # right
                 ("light", [(-0.5, 2.99, -0.5), (0.5, 2.99, -0.5), (0.5, 2.99, 0.5),
                            (-0.5, 2.99, 0.5)])]
        for name, q in quads:
            o.write(f"usemtl {name}\n")
            o.write("".join(f"v {x} {y} {z}\n" for x, y, z in q))
            o.write(f"f {base} {base + 1} {base + 2}\nf {base} {base + 2} {base + 3}\n")
            base += 4
    scene = {
        "_comment": "Two Stanford bunnies in a diffuse box (139,000 triangles): the path "
                    "tracer's mesh benchmark against Cycles (bench/cycles/make_bunny_box.py).",
        "camera": {"type": "perspective", "position": [0, 1.5, 6.2], "look_at": [0, 1.2, 0],
                   "up": [0, 1, 0], "fov": 38},
        "film": {"width": 512, "height": 512},
        "render": {"engine": "path", "spp": 64, "max_depth": 64, "background": 0},
        "materials": {},
        "lights": [],
        "objects": [{"type": "mesh", "file": "bunny_box.obj"}],
    }
    json.dump(scene, open(os.path.join(out, "bunny_box.json"), "w"), indent=2)
    print(f"{2 * len(f) + 12} triangles -> {out}/bunny_box.json")


if __name__ == "__main__":
    main()
