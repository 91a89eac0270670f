#!/usr/bin/python3
"""The pictures and numbers of docs/shadows.md, made again from scenes/shadows.json.

Usage: scripts/shadow_figures.py [SVETLO] (default build/svetlo). Writes docs/images/shadows_*.png
and prints the tables of docs/shadows.md (Markdown) on stdout. Needs Debian's python3-numpy.

Every technique's visibility AOV (light 0's mask) is compared with the raytraced technique's,
which casts shadow rays through the same triangles: the intersection over union of the shadowed
pixels (visibility < 0.5), and the mean absolute difference of the visibility. Times are the
render time svetlo reports (the shadow passes included), on this machine's threads.
"""
import json
import os
import re
import struct
import subprocess
import sys
import tempfile
import zlib

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SVETLO = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "svetlo")
IMAGES = os.path.join(ROOT, "docs", "images")
TMP = tempfile.mkdtemp(prefix="svetlo_shadows_")
BASE = json.load(open(os.path.join(ROOT, "scenes", "shadows.json")))


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.fromfile(f, dtype="<f4" if scale < 0 else ">f4")
    data = data.reshape(height, width, 3 if kind == b"PF" else 1)
    return data[::-1]


def write_png(path, rgb):
    """rgb: float array in [0, 1], height x width x 3 (already display-encoded)."""
    a = (np.clip(rgb, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)
    h, w, _ = a.shape
    raw = b"".join(b"\0" + a[y].tobytes() for y in range(h))

    def chunk(tag, data):
        return (struct.pack(">I", len(data)) + tag + data +
                struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def srgb(linear):
    c = np.clip(linear, 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1 / 2.4) - 0.055)


def render(scene, name, sets=(), aovs=("visibility",)):
    """Renders a scene dict; returns (colour, {aov: image}, render seconds)."""
    path = os.path.join(TMP, name + ".json")
    json.dump(scene, open(path, "w"))
    out = os.path.join(TMP, name + ".pfm")
    cmd = [SVETLO, "render", path, "-o", out]
    for s in sets:
        cmd += ["--set", s]
    for a in aovs:
        cmd += ["--aov", "%s=%s" % (a, os.path.join(TMP, name + "_" + a + ".pfm"))]
    err = subprocess.run(cmd, check=True, capture_output=True, text=True).stderr
    seconds = float(re.search(r"render ([0-9.]+) s", err).group(1))
    result = {a: read_pfm(os.path.join(TMP, name + "_" + a + ".pfm"))[..., 0] for a in aovs}
    return read_pfm(out), result, seconds


def compare(v, truth):
    a, b = v < 0.5, truth < 0.5
    union = (a | b).sum()
    return (a & b).sum() / union if union else 1.0, np.abs(v - truth).mean()


def scene_with(**changes):
    s = json.loads(json.dumps(BASE))
    for key, value in changes.items():
        node = s
        parts = key.split("__")
        for p in parts[:-1]:
            node = node.setdefault(p, {})
        node[parts[-1]] = value
    return s


LIGHTS = {
    "point": {"type": "point", "position": [3.5, 3.6, 4.5], "intensity": [40, 40, 40]},
    "spot": BASE["lights"][0],
    "directional": {"type": "directional", "direction": [-4, -3, -6], "irradiance": [3, 3, 3]},
    "area": {"type": "area", "corner": [3.0, 4.2, 3.2], "edge_u": [1, 0, 0], "edge_v": [0, -0.6, 0.8],
             "radiance": [40, 40, 40]},
}
TECHNIQUES = ["raytraced", "map", "volume", "planar"]


def main():
    os.makedirs(IMAGES, exist_ok=True)
    # 1. The same scene under every technique, with its error against the raytraced one.
    truth_colour, truth, _ = render(BASE, "truth", ["render.shadows=raytraced"])
    row, errors = [], []
    print("| technique | render time (s) | IoU | mean abs. error |")
    print("| --- | --- | --- | --- |")
    for t in TECHNIQUES + ["none"]:
        colour, aov, seconds = render(BASE, "tech_" + t, ["render.shadows=" + t])
        iou, mae = compare(aov["visibility"], truth["visibility"])
        print("| %s | %.3f | %.4f | %.4f |" % (t, seconds, iou, mae))
        if t != "none":
            row.append(srgb(colour))
            # Red where the visibility differs, over the picture in faint grey.
            diff = np.abs(aov["visibility"] - truth["visibility"])[..., None]
            grey = 0.35 * srgb(colour).mean(axis=-1, keepdims=True)
            errors.append((1 - diff) * grey + diff * np.array([1.0, 0.0, 0.0]))
            write_png(os.path.join(IMAGES, "shadows_%s.png" % t), srgb(colour))
    write_png(os.path.join(IMAGES, "shadows_errors.png"),
              np.concatenate([e[::2, ::2] for e in errors], axis=1))
    # 2. Shadows versus types of light.
    print()
    print("| technique | " + " | ".join(LIGHTS) + " |")
    print("| --- |" + " --- |" * len(LIGHTS))
    cells = {t: [] for t in TECHNIQUES[1:]}
    for light, value in LIGHTS.items():
        s = scene_with(lights=[value])
        _, ref, ref_s = render(s, "light_" + light + "_rt", ["render.shadows=raytraced"])
        for t in TECHNIQUES[1:]:
            _, aov, seconds = render(s, "light_%s_%s" % (light, t), ["render.shadows=" + t])
            iou, mae = compare(aov["visibility"], ref["visibility"])
            cells[t].append("%.3f / %.4f / %.2f s" % (iou, mae, seconds))
    for t, c in cells.items():
        print("| %s | %s |" % (t, " | ".join(c)))
    # 3. Failures.
    failures = [
        ("acne", ["render.shadows=map", "render.shadow_map.filter=none", "render.shadow_map.bias=0",
                  "render.shadow_map.normal_offset=0", "render.shadow_map.slope_bias=0"]),
        ("peter_panning", ["render.shadows=map", "render.shadow_map.bias=0.25",
                           "render.shadow_map.normal_offset=20"]),
        ("aliasing", ["render.shadows=map", "render.shadow_map.filter=none",
                      "render.shadow_map.resolution=128"]),
        ("aliasing_pcf", ["render.shadows=map", "render.shadow_map.filter=pcf",
                          "render.shadow_map.kernel=5", "render.shadow_map.resolution=128"]),
    ]
    print()
    for name, sets in failures:
        colour, aov, _ = render(BASE, "fail_" + name, sets)
        write_png(os.path.join(IMAGES, "shadows_%s.png" % name), srgb(colour)[::2, ::2])
        iou, mae = compare(aov["visibility"], truth["visibility"])
        print("%s: IoU %.4f, mean abs. error %.4f" % (name, iou, mae))
    # False planar shadows: a card above the light, projected whole through it.
    # The light above the wall; the card on the line from the floor's middle through the
    # light, beyond it: its false shadow, mirrored through the light, lands mid-floor.
    above = scene_with(lights=[{"type": "point", "position": [3.5, 5, 4.5], "intensity": [60] * 3}])
    above["objects"].append({"type": "quad", "corner": [4.3, 6.5, 5.6], "edge_u": [0.5, 0, 0],
                             "edge_v": [0, 0, 0.5], "material": "card"})
    for clip in (True, False):
        colour, aov, _ = render(above, "planar_clip_%d" % clip,
                                ["render.shadows=planar", "render.planar_shadows.clip=%s" %
                                 ("true" if clip else "false")])
        write_png(os.path.join(IMAGES, "shadows_planar_%s.png" % ("clipped" if clip else "false")),
                  srgb(colour)[::2, ::2])
    # z-pass against z-fail, the camera in the sphere's shadow.
    inside = scene_with(camera={"type": "perspective", "position": [-2.3, 0.25, -0.6],
                                "look_at": [2.0, 0.5, -1.5], "up": [0, 1, 0], "fov": 75})
    for count in ("zfail", "zpass"):
        colour, aov, _ = render(inside, "inside_" + count,
                                ["render.shadows=volume", "render.shadow_volume.count=" + count])
        write_png(os.path.join(IMAGES, "shadows_inside_%s.png" % count), srgb(colour)[::2, ::2])
    # 4. Filters under an area light.
    area = scene_with(lights=[LIGHTS["area"]])
    crops = []
    print()
    _, ref, _ = render(area, "area_rt", ["render.shadows=raytraced"])
    for name, sets in [("raytraced", ["render.shadows=raytraced"]),
                       ("16 point maps", ["render.shadows=map", "render.shadow_map.filter=none"]),
                       ("16 point maps, PCF 3", ["render.shadows=map"]),
                       ("PCSS", ["render.shadows=map", "render.shadow_map.filter=pcss",
                                 "render.shadow_map.kernel=7"]),
                       ("16 point volumes", ["render.shadows=volume"])]:
        colour, aov, seconds = render(area, "area_" + re.sub(r"\W", "_", name), sets)
        iou, mae = compare(aov["visibility"], ref["visibility"])
        print("| %s | %.4f | %.3f |" % (name, mae, seconds))
        if "PCF" not in name:
            crops.append(srgb(colour)[70:250, 30:330])
    write_png(os.path.join(IMAGES, "shadows_area.png"),
              np.concatenate([np.concatenate(crops[:2], axis=1), np.concatenate(crops[2:], axis=1)]))
    # 5. The debug buffers.
    point = scene_with(lights=[LIGHTS["point"]])
    _, aov, _ = render(point, "debug_map", ["render.shadows=map", "render.shadow_map.resolution=256"],
                       aovs=("shadow_map",))
    m = aov["shadow_map"]
    hit = m[m > 0]
    shown = np.where(m > 0, 1.0 - np.clip(m / np.percentile(hit, 99), 0, 1), 0.0)
    write_png(os.path.join(IMAGES, "shadows_cube_map.png"), np.stack([shown] * 3, axis=-1))
    _, aov, _ = render(point, "debug_stencil", ["render.shadows=volume"], aovs=("stencil",))
    count = np.abs(aov["stencil"])
    write_png(os.path.join(IMAGES, "shadows_stencil.png"),
              np.stack([count / max(count.max(), 1)] * 3, axis=-1)[::2, ::2])
    # 6. Cascades on a large scene.
    rng = np.random.default_rng(1)
    big = {"camera": {"type": "perspective", "position": [0, 3, 10], "look_at": [0, 1, -20],
                      "up": [0, 1, 0], "fov": 60},
           "film": {"width": 480, "height": 300},
           "render": {"engine": "raster", "shadows": "map"},
           "materials": {"m": {"type": "lambert", "albedo": 0.8}},
           "lights": [{"type": "directional", "direction": [-0.5, -1, -0.3], "irradiance": 3}],
           "objects": [{"type": "quad", "corner": [-100, 0, -100], "edge_u": [0, 0, 200],
                        "edge_v": [200, 0, 0], "material": "m"}]}
    for _ in range(60):
        big["objects"].append({"type": "sphere", "center": [float(rng.uniform(-40, 40)), 1,
                                                            float(rng.uniform(-90, 5))],
                               "radius": 1, "material": "m"})
    _, ref, _ = render(big, "big_rt", ["render.shadows=raytraced"])
    print()
    shots = []
    for cascades in (1, 4):
        colour, aov, seconds = render(big, "big_%d" % cascades,
                                      ["render.shadow_map.cascades=%d" % cascades,
                                       "render.shadow_map.resolution=1024"])
        iou, mae = compare(aov["visibility"], ref["visibility"])
        print("cascades %d: IoU %.4f, mean abs. error %.4f, %.3f s" % (cascades, iou, mae, seconds))
        shots.append(srgb(colour)[::2, ::2])
    write_png(os.path.join(IMAGES, "shadows_cascades.png"), np.concatenate(shots, axis=1))


if __name__ == "__main__":
    main()
