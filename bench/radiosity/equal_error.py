#!/usr/bin/python3
"""Radiosity against the path tracer at equal error (docs/performance.md, "Radiosity").

A converged reference of the Cornell box (the path tracer at many paths per pixel), then
radiosity's whole solve and display, timed, and its error against the reference (relative RMS
over the pixels that neither see the light nor touch it); then the path tracer at growing sample counts
until its error falls below radiosity's. Prints both times and their ratio.

Usage: bench/radiosity/equal_error.py build/svetlo [SIZE] [REFERENCE_SPP] [THREADS]"""
import re
import subprocess
import sys

import numpy as np

svetlo = sys.argv[1]
size = sys.argv[2] if len(sys.argv) > 2 else "96"
ref_spp = sys.argv[3] if len(sys.argv) > 3 else "8192"
threads = sys.argv[4] if len(sys.argv) > 4 else "2"
scene = "scenes/cornell.json"


def read_pfm(path):
    with open(path, "rb") as f:
        f.readline()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return data.reshape(h, w, 3)[::-1].astype(np.float64)


def render(engine, extra):
    out = f"/tmp/svetlo_eq_{engine}.pfm"
    cmd = [svetlo, "render", scene, "--engine", engine, "-W", size, "-H", size, "-t", threads,
           "-o", out, "--set", "render.max_depth=64"] + extra
    log = subprocess.run(cmd, capture_output=True, text=True, check=True).stderr
    m = re.search(r"setup ([0-9.]+) s, render ([0-9.]+) s", log)
    return read_pfm(out), float(m.group(1)) + float(m.group(2))


reference, _ = render("path", ["--spp", ref_spp])
# The surfaces: not the light, nor a pixel next to it (where the light's coverage, an
# antialiasing question, would outweigh the lighting).
light = reference.mean(axis=2) >= 2.0
near = light.copy()
for dy in (-1, 0, 1):
    for dx in (-1, 0, 1):
        near |= np.roll(np.roll(light, dy, axis=0), dx, axis=1)
surfaces = ~near


def error(image):
    d = (image - reference)[surfaces]
    return float(np.sqrt((d * d).mean()) / reference[surfaces].mean())


rad, rad_seconds = render("radiosity", ["--spp", "16"])
rad_error = error(rad)
print(f"radiosity: {rad_seconds:.3f} s, error {rad_error:.4f}")
path_seconds = None
spp = 1
while spp <= 65536:
    image, seconds = render("path", ["--spp", str(spp), "--seed", "7"])
    e = error(image)
    print(f"path spp={spp}: {seconds:.3f} s, error {e:.4f}")
    if e <= rad_error:
        path_seconds = seconds
        break
    spp *= 2
if path_seconds is None:
    print("the path tracer did not reach radiosity's error")
else:
    print(f"equal error: path {path_seconds:.3f} s / radiosity {rad_seconds:.3f} s = "
          f"{path_seconds / rad_seconds:.1f} x")
