#!/usr/bin/python3
"""Radiosity's benchmarks (docs/performance.md, "Radiosity"), on the Cornell box:

  1. time per shooting step against the number of elements (progressive, a fixed number of
     shots at four refinements): the log-log slope;
  2. time to a residual of 1e-3 and peak memory (GNU time's maximum resident set), for the
     progressive and the hierarchical solvers from about 1k to 200k elements (progressive with
     the default patches, a quarter of the scene's diameter).

Usage: bench/radiosity/scaling.py build/svetlo [THREADS] [--quick]"""
import math
import re
import subprocess
import sys

svetlo = sys.argv[1]
threads = sys.argv[2] if len(sys.argv) > 2 and not sys.argv[2].startswith("-") else "2"
quick = "--quick" in sys.argv
scene = "scenes/cornell.json"


def run(sets):
    """Renders a tiny image (the solve dominates) and returns (seconds, detail, peak MiB)."""
    cmd = ["/usr/bin/time", "-f", "maxrss_kb=%M", svetlo, "render", scene, "--engine",
           "radiosity", "-W", "16", "-H", "16", "--spp", "1", "-t", threads, "-o", "/tmp/rad_bench.pfm"]
    for s in sets:
        cmd += ["--set", s]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stderr
    seconds = float(re.search(r"render ([0-9.]+) s", out).group(1))
    detail = re.search(r"render [0-9.]+ s, (.*) ->", out).group(1)
    rss = int(re.search(r"maxrss_kb=(\d+)", out).group(1)) / 1024.0
    return seconds, detail, rss


def elements(detail):
    return int(re.match(r"(\d+) elements", detail).group(1))


print(f"# radiosity on {scene}, {threads} threads")
print("## time per shot (progressive, 100 shots, analytic form factors, 4 visibility rays)")
points = []
for size in ([0.6, 0.3, 0.15] if quick else [0.6, 0.3, 0.15, 0.075]):
    s, detail, rss = run([f"render.radiosity.element_size={size}", "render.radiosity.adaptive=0",
                          "render.radiosity.solver=progressive", "render.radiosity.max_iterations=100",
                          "render.radiosity.tolerance=1e-9"])
    shots = int(re.search(r"(\d+) shots", detail).group(1))
    n = elements(detail)
    points.append((n, s / shots))
    print(f"elements={n} ms_per_shot={1000 * s / shots:.3f}")
slope = [(math.log(b[1]) - math.log(a[1])) / (math.log(b[0]) - math.log(a[0]))
         for a, b in zip(points, points[1:])]
print("log-log slopes between refinements: " + ", ".join(f"{x:.2f}" for x in slope))

print("## time to a residual of 1e-3 and peak memory")
cases = [("progressive", 0.6), ("progressive", 0.3), ("progressive", 0.15),
         ("hierarchical", 0.6), ("hierarchical", 0.3), ("hierarchical", 0.15)]
if not quick:
    cases += [("progressive", 0.075), ("progressive", 0.0375), ("hierarchical", 0.0375)]
for solver, size in cases:
    sets = [f"render.radiosity.element_size={size}", "render.radiosity.adaptive=0",
            f"render.radiosity.solver={solver}", "render.radiosity.tolerance=1e-3"]
    if solver == "hierarchical":
        sets.append("render.radiosity.max_subdivision=0")
    s, detail, rss = run(sets)
    print(f"solver={solver} elements={elements(detail)} seconds={s:.2f} peak_mib={rss:.0f} ({detail})")
