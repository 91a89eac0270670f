"""svetlo's path tracer against a Cycles ladder: error against time, as a table and a plot.

    /usr/bin/python3 bench/cycles/convergence.py SVETLO SCENE LADDER_DIR OUT.svg [THREADS
        [KEY=VALUE...]]

renders SCENE with svetlo's path engine at 4, 16, 64 and 256 spp (max_depth 64, seeds 0 and
1, the ladder's size), estimates each level's RMSE from the pair as rms(A - B) / sqrt(2) (as
the Cycles harness does with --pairs), reads the ladder's levels from LADDER_DIR/ladder.json
(made by ../shared/anchors/cycles/cycles_cornell.py --ladder ... --pairs), prints both with
the time Cycles needs for svetlo's error (a power law fitted to its levels from 16 spp), and
draws both on log-log axes into OUT.svg. Times are render times: svetlo's "render R s" and
Cycles' render call. Needs numpy only."""
import json
import math
import os
import re
import subprocess
import sys
import tempfile

import numpy as np


def read_pfm(path):
    with open(path, "rb") as f:
        f.readline()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        return np.fromfile(f, dtype="<f4" if scale < 0 else ">f4").reshape(h, w, 3)


def svetlo_level(svetlo, scene, spp, width, height, threads, tmp, sets):
    images, seconds = [], []
    for seed in (0, 1):
        out = os.path.join(tmp, f"sv_{spp}_{seed}.pfm")
        log = subprocess.run([svetlo, "render", scene, "--engine", "path", "--set",
                              "render.max_depth=64", "-W", str(width), "-H", str(height),
                              "--spp", str(spp), "--seed", str(seed), "-t", str(threads),
                              "-o", out] + [a for kv in sets for a in ("--set", kv)],
                             capture_output=True, text=True, check=True).stderr
        seconds.append(float(re.search(r"render ([0-9.]+) s", log).group(1)))
        images.append(read_pfm(out))
    rmse = math.sqrt(float(np.mean((images[0] - images[1]) ** 2)) / 2.0)
    return {"spp": spp, "seconds": float(np.mean(seconds)), "rmse": rmse,
            "mean": images[0].mean(axis=(0, 1)).tolist()}


def print_equal_error(cycles, svetlo):
    """Fits Cycles' RMSE = c t^b over its levels (log-log least squares) and prints both
    ladders, each svetlo level with the time Cycles needs for its RMSE. A level is a dict of
    spp, seconds and rmse."""
    b, log_c = np.polyfit(np.log([l["seconds"] for l in cycles]), np.log([l["rmse"] for l in cycles]), 1)
    print(f"Cycles: RMSE = {math.exp(log_c):.4g} t^{b:.3f}")
    for l in cycles:
        print(f"  Cycles {l['spp']:5d} spp {l['seconds']:8.2f} s  RMSE {l['rmse']:.5f}")
    for s in svetlo:
        t_cycles = math.exp((math.log(s["rmse"]) - log_c) / b)
        print(f"  svetlo {s['spp']:5d} spp {s['seconds']:8.2f} s  RMSE {s['rmse']:.5f}  "
              f"Cycles needs {t_cycles:8.2f} s: svetlo is x{t_cycles / s['seconds']:.2f} as fast")


def svg_plot(path, series, title):
    """series: [(label, colour, [(seconds, rmse)])] on log-log axes."""
    W, H, L, R, T, B = 640, 420, 70, 20, 40, 50
    xs = [p[0] for _, _, pts in series for p in pts]
    ys = [p[1] for _, _, pts in series for p in pts]
    x0, x1 = math.floor(math.log10(min(xs))), math.ceil(math.log10(max(xs)))
    y0, y1 = math.floor(math.log10(min(ys))), math.ceil(math.log10(max(ys)))
    fx = lambda x: L + (math.log10(x) - x0) / (x1 - x0) * (W - L - R)
    fy = lambda y: H - B - (math.log10(y) - y0) / (y1 - y0) * (H - T - B)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" '
           f'font-family="sans-serif" font-size="12"><rect width="{W}" height="{H}" fill="white"/>',
           f'<text x="{W / 2}" y="20" text-anchor="middle" font-size="14">{title}</text>']
    for e in range(x0, x1 + 1):
        out.append(f'<line x1="{fx(10 ** e)}" y1="{T}" x2="{fx(10 ** e)}" y2="{H - B}" stroke="#ddd"/>')
        out.append(f'<text x="{fx(10 ** e)}" y="{H - B + 16}" text-anchor="middle">{10.0 ** e:g} s</text>')
    for e in range(y0, y1 + 1):
        out.append(f'<line x1="{L}" y1="{fy(10 ** e)}" x2="{W - R}" y2="{fy(10 ** e)}" stroke="#ddd"/>')
        out.append(f'<text x="{L - 6}" y="{fy(10 ** e) + 4}" text-anchor="end">{10.0 ** e:g}</text>')
    out.append(f'<text x="{W / 2}" y="{H - 12}" text-anchor="middle">render time</text>')
    out.append(f'<text x="16" y="{H / 2}" transform="rotate(-90 16 {H / 2})" '
               f'text-anchor="middle">RMSE</text>')
    for k, (label, colour, pts) in enumerate(series):
        d = " ".join(f"{fx(x):.1f},{fy(y):.1f}" for x, y in pts)
        out.append(f'<polyline points="{d}" fill="none" stroke="{colour}" stroke-width="2"/>')
        for x, y in pts:
            out.append(f'<circle cx="{fx(x):.1f}" cy="{fy(y):.1f}" r="3.5" fill="{colour}"/>')
        out.append(f'<text x="{W - R - 150}" y="{T + 20 + 18 * k}" fill="{colour}">{label}</text>')
    out.append("</svg>")
    open(path, "w").write("\n".join(out))


def main():
    svetlo, scene, ladder_dir, svg = sys.argv[1:5]
    threads = int(sys.argv[5]) if len(sys.argv) > 5 else 2
    sets = sys.argv[6:]  # more --set overrides for svetlo
    ladder = json.load(open(os.path.join(ladder_dir, "ladder.json")))
    width, height = ladder["width"], ladder["height"]
    levels = [{"spp": l["spp"], "seconds": l["seconds"], "rmse": l.get("rmse", l.get("rmse_pair"))}
              for l in ladder["levels"] if l["spp"] >= 16]
    cyc = [(l["seconds"], l["rmse"]) for l in levels]
    tmp = tempfile.mkdtemp(prefix="svetlo_convergence_")
    sv = [svetlo_level(svetlo, scene, spp, width, height, threads, tmp, sets)
          for spp in (4, 16, 64, 256)]
    print(f"Cycles {width}x{height}, {ladder.get('threads', '?')} threads")
    print_equal_error(levels, sv)
    svg_plot(svg, [("Cycles 3.4", "#c0392b", cyc),
                   ("svetlo path", "#2060c0", [(s["seconds"], s["rmse"]) for s in sv])],
             f"{os.path.basename(scene)}, {width}x{height}, {threads} threads")


if __name__ == "__main__":
    main()
