"""Shadow-map bias against its two artefacts, measured against ray-traced visibility
(docs/python.md, docs/shadows.md).

Too little bias and a surface shadows itself: shadow acne, pixels the map darkens that a
shadow ray finds lit. Too much and shadows detach from their casters: peter-panning, pixels
the map lights that a shadow ray finds shadowed. This sweeps render.shadow_map.bias, counts
both against the rasterizer's own ray-traced shadows (render.shadows "raytraced"), and plots
them when Debian's python3-matplotlib is there (else prints the table).

    PYTHONPATH=build/python python3 examples/python/shadow_bias_sweep.py [--quick] [-o plot.png]
"""
import argparse
import os

import numpy as np

import svetlo

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a small film and few biases (tests)")
    parser.add_argument("-o", "--output", default="shadow_bias_sweep.png", help="the plot")
    args = parser.parse_args()
    size = dict(width=120, height=75) if args.quick else dict(width=480, height=300)
    biases = np.geomspace(1e-5, 1.0, 6 if args.quick else 24)

    scene = svetlo.load(os.path.join(ROOT, "scenes", "shadows.json"))
    # Hard shadows, one sample a pixel: each pixel is lit or not, under both techniques.
    scene["render.spp"] = 1
    scene["render.shadow_map.filter"] = "none"
    scene["render.shadow_map.normal_offset"] = 0
    scene["render.shadow_map.slope_bias"] = 0
    truth = svetlo.render(scene, set={"render.shadows": "raytraced"}, aovs=["visibility"],
                          **size).aovs["visibility"][..., 0]
    lit = truth > 0.5
    rows = []
    for bias in biases:
        vis = svetlo.render(scene, set={"render.shadows": "map", "render.shadow_map.bias": float(bias)},
                            aovs=["visibility"], **size).aovs["visibility"][..., 0] > 0.5
        acne = np.count_nonzero(lit & ~vis)        # lit, but the map says shadow
        peter = np.count_nonzero(~lit & vis)       # shadowed, but the map says lit
        rows.append((bias, acne, peter))
    print("%12s %8s %14s" % ("bias (m)", "acne", "peter-panning"))
    for bias, acne, peter in rows:
        print("%12.3g %8d %14d" % (bias, acne, peter))
    best = min(rows, key=lambda r: r[1] + r[2])
    print("fewest wrong pixels: %d at bias %.3g m" % (best[1] + best[2], best[0]))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("(python3-matplotlib is not installed: no plot)")
        return
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.loglog([r[0] for r in rows], [max(r[1], 0.5) for r in rows], "o-", label="acne")
    ax.loglog([r[0] for r in rows], [max(r[2], 0.5) for r in rows], "s-", label="peter-panning")
    ax.set_xlabel("render.shadow_map.bias (m)")
    ax.set_ylabel("wrong pixels")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print("wrote", args.output)


if __name__ == "__main__":
    main()
