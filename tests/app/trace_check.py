"""Checks a `svetlo trace --json` file against the pixel the engine rendered, without svetlo,
for tests/app/trace_test.sh.

  trace_check.py TRACE.json PIXEL.pfm|- [OBJ]

Exit 0 when: the object has the keys of docs/trace.md; every ray has kind, origin, direction, t and
contribution, its kind one of those listed there, its parent before it; `total` equals the
rendered pixel within 1e-5; the contributions sum to the total (relative 1e-4); and the OBJ,
when given, draws one segment per ray.
"""
import json
import math
import sys

from pfm_tool import read

KINDS = {"camera", "reflect", "refract", "shadow", "bsdf", "light"}


def fail(why):
    print("trace_check: " + why)
    sys.exit(1)


def main():
    trace = json.load(open(sys.argv[1]))
    for key in ("pixel", "sample", "engine", "total", "rays"):
        if key not in trace:
            fail("no key " + key)
    rays = trace["rays"]
    if not rays or rays[0]["kind"] != "camera":
        fail("the first ray is not the camera's")
    for k, ray in enumerate(rays):
        for key in ("kind", "origin", "direction", "t", "contribution"):
            if key not in ray:
                fail("ray %d has no %s" % (k, key))
        if ray["kind"] not in KINDS:
            fail("ray %d is of kind %s" % (k, ray["kind"]))
        if not -1 <= ray["parent"] < k:
            fail("ray %d's parent %d does not come before it" % (k, ray["parent"]))
        if ray["t"] is not None and not ray["t"] > 0:
            fail("ray %d's t is %s" % (k, ray["t"]))
        if abs(math.hypot(*ray["direction"]) - 1) > 1e-4:
            fail("ray %d's direction is not unit" % k)
    total = trace["total"]
    pixel = total  # "-": a sample other than the render's own
    if sys.argv[2] != "-":
        w, h, rows = read(sys.argv[2])
        if (w, h) != (1, 1):
            fail("the render is not one pixel")
        pixel = rows[0][0:3]
    for c in range(3):
        if abs(total[c] - pixel[c]) > 1e-5:
            fail("total %s, the render's pixel %s" % (total, list(pixel)))
        added = sum(ray["contribution"][c] for ray in rays)
        if abs(added - total[c]) > 1e-4 * abs(total[c]) + 1e-6:
            fail("the contributions add up to %g, the total is %g (channel %d)" % (added, total[c], c))
    if len(sys.argv) > 3:
        segments = [line for line in open(sys.argv[3]) if line.startswith("l ")]
        if len(segments) != len(rays):
            fail("the OBJ has %d segments for %d rays" % (len(segments), len(rays)))
    print("%s: %d rays, total %s" % (trace["engine"], len(rays), total))


if __name__ == "__main__":
    main()
