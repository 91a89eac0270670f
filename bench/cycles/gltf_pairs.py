"""svetlo's path tracer and Cycles side by side on glTF models under an environment: the
docs' picture (each pair svetlo left, Cycles right, two pairs a row) and the FLIP of each pair
with Cycles' own seed-to-seed floor, the mean luminance of the model's pixels (where svetlo's
depth AOV is not 0) in each and the median of their ratio there, as a Markdown table.

    /usr/bin/python3 bench/cycles/gltf_pairs.py SVETLO ENV OUT.png MODEL[:principled]...
        [--size 160] [--spp 256] [--threads 2] [--bounces 16]

A model marked `:principled` keeps the importer's Principled BSDF in Cycles (the harness's
rewiring to the glTF BRDF leaves transmission out). Each model is seen from the camera svetlo
frames it with, lit by ENV alone. Needs numpy and Blender (`scripts/setup cycles`)."""
import argparse
import os
import re
import subprocess
import tempfile
import zlib
import struct

import numpy as np

from convergence import read_pfm
from gltf_convergence import camera_of, svetlo_args


def write_png(path, rgb):
    """Linear RGB, clipped to [0, 1] and encoded as sRGB, top row first."""
    a = np.clip(rgb, 0.0, 1.0)
    a = np.where(a <= 0.0031308, 12.92 * a, 1.055 * a ** (1 / 2.4) - 0.055)
    a = (a * 255.0 + 0.5).astype(np.uint8)
    h, w, _ = a.shape
    raw = b"".join(b"\0" + a[y].tobytes() for y in range(h))
    chunk = lambda t, d: (struct.pack(">I", len(d)) + t + d +
                          struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def luminance(rgb):
    """Rec. 709 luminance of linear RGB."""
    return rgb @ np.array([0.2126, 0.7152, 0.0722])


def flip(svetlo, a, b):
    out = subprocess.run([svetlo, "diff", a, b], capture_output=True, text=True).stdout
    return float(re.search(r"flip ([0-9.eE+-]+)", out).group(1))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("svetlo")
    p.add_argument("env")
    p.add_argument("png")
    p.add_argument("models", nargs="+")
    p.add_argument("--size", type=int, default=160)
    p.add_argument("--spp", type=int, default=256)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--bounces", type=int, default=16)
    here = os.path.dirname(os.path.abspath(__file__))
    p.add_argument("--harness", default=os.path.join(here, "../../../shared/anchors/cycles"))
    a = p.parse_args()
    tmp = tempfile.mkdtemp(prefix="svetlo_gltf_pairs_")
    tiles, rows = [], []
    for k, spec in enumerate(a.models):
        model, _, mode = spec.partition(":")
        camera = camera_of(a.svetlo, model)
        sv = os.path.join(tmp, f"sv_{k}.pfm")
        depth = os.path.join(tmp, f"depth_{k}.pfm")
        subprocess.run([a.svetlo, "render"] + svetlo_args(model, a.env, camera, a.size, a.threads,
                                                          a.bounces) +
                       ["--spp", str(a.spp), "-o", sv, "--aov", f"depth={depth}", "-q"],
                       check=True)
        cy = os.path.join(tmp, f"cy_{k}.pfm")
        subprocess.run(["blender", "-b", "--factory-startup", "--python",
                        os.path.join(a.harness, "cycles_gltf.py"), "--", "--model",
                        os.path.abspath(model), "--camera", str(camera).replace("'", '"'),
                        "--env", os.path.abspath(a.env), "--spp", str(a.spp), "--width",
                        str(a.size), "--height", str(a.size), "--threads", str(a.threads),
                        "--bounces", str(a.bounces), "--repeat", "2", "--seed", "0", "--out", cy] +
                       (["--principled"] if mode == "principled" else []),
                       capture_output=True, check=True)
        floor = flip(a.svetlo, cy, cy.replace(".pfm", "_1.pfm"))
        sv_rgb, cy_rgb = read_pfm(sv), read_pfm(cy)
        # The model's pixels: where svetlo's depth AOV is not 0 (a camera ray meets the model).
        on = read_pfm(depth)[..., 0] > 0.0
        lum_sv, lum_cy = luminance(sv_rgb)[on], luminance(cy_rgb)[on]
        # Per pixel, the middle of svetlo's luminance over Cycles': a systematic difference,
        # which Cycles' fireflies (they move the mean and the FLIP) do not move.
        ratio = np.median(lum_sv / np.maximum(lum_cy, 1e-6))
        rows.append(f"| {os.path.basename(model)}{' (Principled)' if mode else ''} | "
                    f"{floor:.3f} | {flip(a.svetlo, sv, cy):.3f} | {lum_sv.mean():.4f} / "
                    f"{lum_cy.mean():.4f} | {ratio:.3f} |")
        tiles.append((sv_rgb[::-1], cy_rgb[::-1]))  # PFM rows run bottom up
    gap = 4
    s = a.size
    cols = 2
    n_rows = (len(tiles) + cols - 1) // cols
    out = np.ones((n_rows * s + (n_rows - 1) * gap, cols * 2 * s + (cols * 2 - 1) * gap, 3))
    for k, pair in enumerate(tiles):
        for j, im in enumerate(pair):
            y, x = (k // cols) * (s + gap), ((k % cols) * 2 + j) * (s + gap)
            out[y:y + s, x:x + s] = im
    write_png(a.png, out)
    print("| model | FLIP, Cycles seed 0 vs seed 1 | FLIP, svetlo vs Cycles | the model's mean "
          "luminance, svetlo / Cycles | median of svetlo ÷ Cycles over its pixels |")
    print("| --- | --- | --- | --- | --- |")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
