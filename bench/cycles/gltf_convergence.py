"""svetlo's path tracer against Cycles on a glTF model under an environment: error against
time over the model's pixels, as a table and a plot.

    /usr/bin/python3 bench/cycles/gltf_convergence.py SVETLO MODEL ENV OUT.svg [--size N]
        [--threads T] [--bounces B] [--cycles-spp 16,64,256] [--svetlo-spp 4,16,64,256]
        [--harness ../shared/anchors/cycles]

Both renderers see the model from the camera svetlo frames it with (`svetlo info MODEL`), lit
by ENV alone, max_depth / bounces B (16). Each level is rendered twice (seeds 0 and 1) and its
RMSE estimated from the pair as rms(A - B) / sqrt(2), as convergence.py does, but only over the
model's pixels: where svetlo's depth AOV finds the model in the pixel and in its eight
neighbours (where the camera sees the environment itself, both renderers only jitter the
pixel, and the silhouette's pixels mix the two). Cycles runs the harness's cycles_gltf.py
(Blender's own importer, the materials rewired to the glTF BRDF) with --repeat 2; its times
are the render calls', svetlo's its "render R s". A power law fitted to Cycles' levels gives the
time Cycles needs for each svetlo level's error. Needs numpy and Blender (`scripts/setup cycles`)."""
import argparse
import math
import os
import re
import subprocess
import tempfile

import numpy as np

from convergence import print_equal_error, read_pfm, svg_plot


def camera_of(svetlo, model):
    info = subprocess.run([svetlo, "info", model], capture_output=True, text=True, check=True).stdout
    m = re.search(r"camera\s+perspective at \(([^)]*)\) looking at \(([^)]*)\), fov ([0-9.]+)", info)
    if not m:
        raise SystemExit(f"gltf_convergence: no perspective camera in `svetlo info {model}`")
    vec = lambda s: [float(x) for x in s.split(",")]
    return {"position": vec(m.group(1)), "look_at": vec(m.group(2)), "up": [0, 1, 0],
            "fov": float(m.group(3))}


def svetlo_args(model, env, camera, size, threads, bounces):
    cam = ",".join(f'"{k}": {v}' for k, v in camera.items())
    return [model, "-e", "path", "-W", str(size), "-H", str(size), "-t", str(threads),
            "--set", f"render.max_depth={bounces}", "--set", "lights=[]",
            "--set", f'environment={{"file": "{os.path.abspath(env)}"}}',
            "--set", f"camera={{{cam}}}".replace("'", '"')]


def model_mask(svetlo, args, tmp):
    depth = os.path.join(tmp, "depth.pfm")
    subprocess.run([svetlo, "render"] + args + ["--spp", "16", "-o", os.path.join(tmp, "m.pfm"),
                                                "--aov", f"depth={depth}", "-q"], check=True)
    hit = read_pfm(depth)[..., 0] > 0.0
    inside = hit.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            inside &= np.roll(np.roll(hit, dy, axis=0), dx, axis=1)
    inside[0, :] = inside[-1, :] = inside[:, 0] = inside[:, -1] = False
    return inside


def pair_rmse(a, b, mask):
    return math.sqrt(float(np.mean(((a - b) ** 2)[mask])) / 2.0)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("svetlo")
    p.add_argument("model")
    p.add_argument("env")
    p.add_argument("svg")
    p.add_argument("--size", type=int, default=256)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--bounces", type=int, default=16)
    p.add_argument("--cycles-spp", default="16,64,256")
    p.add_argument("--svetlo-spp", default="4,16,64,256")
    here = os.path.dirname(os.path.abspath(__file__))
    p.add_argument("--harness", default=os.path.join(here, "../../../shared/anchors/cycles"))
    a = p.parse_args()
    tmp = tempfile.mkdtemp(prefix="svetlo_gltf_convergence_")
    camera = camera_of(a.svetlo, a.model)
    args = svetlo_args(a.model, a.env, camera, a.size, a.threads, a.bounces)
    mask = model_mask(a.svetlo, args, tmp)
    print(f"{os.path.basename(a.model)} under {os.path.basename(a.env)}, {a.size}x{a.size}, "
          f"{a.threads} threads, {a.bounces} bounces: {int(mask.sum())} model pixels")

    cyc = []
    for spp in [int(s) for s in a.cycles_spp.split(",")]:
        out = os.path.join(tmp, f"cy_{spp}.pfm")
        log = subprocess.run(
            ["blender", "-b", "--factory-startup", "--python",
             os.path.join(a.harness, "cycles_gltf.py"), "--", "--model", os.path.abspath(a.model),
             "--camera", str(camera).replace("'", '"'), "--env", os.path.abspath(a.env),
             "--spp", str(spp), "--width", str(a.size), "--height", str(a.size),
             "--threads", str(a.threads), "--bounces", str(a.bounces), "--repeat", "2",
             "--seed", "0", "--out", out], capture_output=True, text=True, check=True).stdout
        seconds = [float(t) for t in re.findall(r"cycles_gltf: render ([0-9.]+) s", log)]
        images = [read_pfm(out), read_pfm(out.replace(".pfm", "_1.pfm"))]
        cyc.append({"spp": spp, "seconds": float(np.mean(seconds)),
                    "rmse": pair_rmse(images[0], images[1], mask)})
    sv = []
    for spp in [int(s) for s in a.svetlo_spp.split(",")]:
        images, seconds = [], []
        for seed in (0, 1):
            out = os.path.join(tmp, f"sv_{spp}_{seed}.pfm")
            log = subprocess.run([a.svetlo, "render"] + args + ["--spp", str(spp), "--seed", str(seed),
                                                                "-o", out],
                                 capture_output=True, text=True, check=True).stderr
            seconds.append(float(re.search(r"render ([0-9.]+) s", log).group(1)))
            images.append(read_pfm(out))
        sv.append({"spp": spp, "seconds": float(np.mean(seconds)),
                   "rmse": pair_rmse(images[0], images[1], mask)})

    print_equal_error(cyc, sv)
    svg_plot(a.svg, [("Cycles 3.4", "#c0392b", [(l["seconds"], l["rmse"]) for l in cyc]),
                     ("svetlo path", "#2060c0", [(s["seconds"], s["rmse"]) for s in sv])],
             f"{os.path.basename(a.model)}, {os.path.basename(a.env)}, {a.size}x{a.size}, "
             f"{a.threads} threads")


if __name__ == "__main__":
    main()
