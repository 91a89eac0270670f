"""The path tracer against radiosity on the Cornell box: error against time (docs/python.md).

The path tracer is unbiased: its error falls as 1 / sqrt(time), to zero. Radiosity is fast
and smooth but biased: it sees only diffuse light, on a mesh of elements, and its error
stops falling where the mesh's resolution does. This renders the path tracer at doubling
samples per pixel and radiosity at finer and finer elements, measures each against a
converged path-traced reference with svetlo.diff, and plots relMSE against seconds (with
Debian's python3-matplotlib) or prints the table.

    PYTHONPATH=build/python python3 examples/python/convergence.py [--quick] [-o plot.png]
"""
import argparse
import os

import svetlo

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a small film, few points (tests)")
    parser.add_argument("-o", "--output", default="convergence.png", help="the plot")
    args = parser.parse_args()
    size = dict(width=48, height=48) if args.quick else dict(width=256, height=256)
    scene = svetlo.load(os.path.join(ROOT, "scenes", "cornell_radiosity.json"))
    scene["render.spp"] = 4  # radiosity's display samples; the path tracer's are set below

    reference = svetlo.render(scene, engine="path", spp=64 if args.quick else 1024, seed=7, **size)
    curves = {"path": [], "radiosity": []}
    for spp in ([1, 4, 16] if args.quick else [1, 2, 4, 8, 16, 32, 64, 128]):
        r = svetlo.render(scene, engine="path", spp=spp, seed=1, **size)
        curves["path"].append((r.stats["seconds"], svetlo.diff(r.image, reference.image, "relmse")))
    for element in ([0.25, 0.1] if args.quick else [0.5, 0.25, 0.12, 0.06, 0.03]):
        r = svetlo.render(scene, engine="radiosity", set={"render.radiosity.element_size": element,
                                                          "render.radiosity.patch_size": 4 * element},
                          **size)
        curves["radiosity"].append((r.stats["seconds"] + r.stats["setup_seconds"],
                                    svetlo.diff(r.image, reference.image, "relmse")))
    for name, points in curves.items():
        print(name)
        for seconds, error in points:
            print("  %8.3f s  relMSE %.5g" % (seconds, error))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("(python3-matplotlib is not installed: no plot)")
        return
    fig, ax = plt.subplots(figsize=(6, 4))
    for name, points in curves.items():
        ax.loglog([p[0] for p in points], [p[1] for p in points], "o-", label=name)
    ax.set_xlabel("seconds")
    ax.set_ylabel("relMSE against the reference")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print("wrote", args.output)


if __name__ == "__main__":
    main()
