"""What calling svetlo from Python costs (docs/python.md): the mean wall-clock time of
svetlo.render against the same job run in C++ with no Python in the loop
(_svetlo.native_render_seconds), on renders small enough that the overhead shows: raster and
path at 64 x 64. Run by `make bench`.

    PYTHONPATH=build/python python3 bench/python_overhead.py [REPEATS]
"""
import os
import sys
import time

import svetlo
from svetlo import _svetlo

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 200
    scene = svetlo.load(os.path.join(ROOT, "scenes", "cornell.json"))
    for engine, spp in (("raster", 1), ("path", 1)):
        kwargs = dict(engine=engine, spp=spp, width=64, height=64, threads=1)
        overrides, keywords = svetlo._request(scene, engine, 64, 64, spp, None, None)
        svetlo.render(scene, **kwargs)  # warm
        best_py, best_native = float("inf"), float("inf")
        for _ in range(5):  # interleaved, best of five
            t0 = time.perf_counter()
            for _ in range(repeats):
                svetlo.render(scene, **kwargs)
            best_py = min(best_py, (time.perf_counter() - t0) / repeats)
            best_native = min(best_native, _svetlo.native_render_seconds(
                scene._text, scene._path, scene._sha256, overrides, keywords, 1, repeats))
        print("%-7s 64x64: python %.3f ms, C++ %.3f ms, overhead %.3f ms a call"
              % (engine, 1e3 * best_py, 1e3 * best_native, 1e3 * (best_py - best_native)))


if __name__ == "__main__":
    main()
