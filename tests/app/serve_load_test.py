"""svetlo serve under load (docs/viewer.md, "Under load"):

1. CLIENTS clients at once, each asking ROUNDS times for renders of several scenes and
   engines, so that requests share the server's mesh and BVH caches: every answer must be an
   image (200), and every client's image of one request the same bytes (the caches change
   nothing);
2. CLIENTS clients moving sliders (the light, the shadow map's bias and resolution, the
   shadow technique: random values) for SECONDS: every request answered with an image, and
   the server's peak memory (VmHWM) under 1 GiB;
3. a closed tab: a long progressive path render whose client goes away after its first frame
   ends, after which the server is idle.

Prints the latencies (median, 95th percentile, worst) and the peak memory.

    serve_load_test.py SVETLO SCENES_DIR [CLIENTS [ROUNDS [SECONDS]]]
"""
import http.client
import json
import os
import random
import re
import shutil
import socket
import subprocess
import sys
import tempfile
import threading
import time
import urllib.error
import urllib.parse
import urllib.request

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from png_chunks import without_text  # noqa: E402

svetlo, scenes = sys.argv[1], sys.argv[2]
clients = int(sys.argv[3]) if len(sys.argv) > 3 else 20
rounds = int(sys.argv[4]) if len(sys.argv) > 4 else 4
seconds = float(sys.argv[5]) if len(sys.argv) > 5 else 10.0
MEMORY_BOUND = 1 << 30  # bytes of the server's peak resident memory

# Small films: the load, not the renders, is what is tested. Five scenes and the four
# engines; bunny.json's mesh and BVH are the large ones. Its mesh is the workplace's public
# data (../shared/data, beside the repository), outside the scene folder, where the server
# reads nothing (docs/viewer.md): the server serves a copy of the folder with the mesh in it,
# and bunny.json naming it there. Where the mesh is absent, cornell.json's stands in.
BUNNY = os.path.join(scenes, "..", "..", "shared", "data", "bunny", "bun_zipper.ply")
served = tempfile.mkdtemp(prefix="svetlo_served_")
shutil.copytree(scenes, served, dirs_exist_ok=True)
LARGE = "bunny.json" if os.path.isfile(BUNNY) else "cornell.json"
if LARGE == "bunny.json":
    shutil.copy(BUNNY, os.path.join(served, "models", "bun_zipper.ply"))
    with open(os.path.join(scenes, "bunny.json")) as f:
        text = f.read().replace("../../shared/data/bunny/", "models/")
    with open(os.path.join(served, "bunny.json"), "w") as f:
        f.write(text)
else:
    print("bunny.json's mesh is absent (%s): cornell.json's instead" % BUNNY)
REQUESTS = [
    "scene=%s&engine=path&spp=1&width=64&height=48" % LARGE,
    "scene=%s&engine=whitted&spp=1&width=64&height=48" % LARGE,
    "scene=cornell.json&engine=path&spp=2&width=48&height=48",
    "scene=shadows.json&engine=raster&spp=1&width=96&height=60",
    "scene=spheres.json&engine=whitted&spp=1&width=64&height=40",
    "scene=cornell_radiosity.json&engine=radiosity&spp=1&width=32&height=32",
]
PNG = b"\x89PNG\r\n\x1a\n"

failures = []


def check(name, ok, detail=""):
    print(("ok   " if ok else "FAIL ") + name + ("" if ok else ": " + str(detail)))
    if not ok:
        failures.append(name)


def get(port, query):
    """The status and body of a render; a PNG without its provenance (png_chunks.py), so that
    equal bodies mean equal images."""
    url = "http://127.0.0.1:%d/api/render?%s" % (port, query)
    try:
        with urllib.request.urlopen(url, timeout=120) as r:
            return r.status, without_text(r.read())
    except urllib.error.HTTPError as e:
        return e.code, e.read()


def report(what, latencies, count, wall):
    latencies.sort()
    print("%s: latency median %.3f s, 95th percentile %.3f s, worst %.3f s; %d requests in "
          "%.1f s (%.1f a second)" % (what, latencies[len(latencies) // 2],
                                     latencies[int(0.95 * (len(latencies) - 1))], latencies[-1],
                                     count, wall, count / wall))


def run_clients(count, work):
    threads = [threading.Thread(target=work, args=(k,)) for k in range(count)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()


server = subprocess.Popen([svetlo, "serve", served, "--port", "0"], stderr=subprocess.PIPE,
                          text=True)


try:
    line = server.stderr.readline()
    m = re.match(r"svetlo: serving http://127\.0\.0\.1:(\d+)/$", line.strip())
    if not m:
        print("FAIL the server's line: " + line)
        sys.exit(1)
    port = int(m.group(1))
    lock = threading.Lock()

    # 1. Fixed requests, the same bytes for every client.
    results, latencies, errors = {}, [], []

    def client(k):
        for r in range(rounds):
            for j in range(len(REQUESTS)):
                query = REQUESTS[(j + k + r) % len(REQUESTS)]
                t0 = time.monotonic()
                status, body = get(port, query + "&client=load%d" % k)
                with lock:
                    latencies.append(time.monotonic() - t0)
                    if status != 200 or body[:8] != PNG:
                        errors.append((query, status, body[:120]))
                    else:
                        results.setdefault(query, set()).add(body)

    start = time.monotonic()
    run_clients(clients, client)
    total = clients * rounds * len(REQUESTS)
    report("fixed requests", latencies, total, time.monotonic() - start)
    check("%d requests from %d clients: every one an image" % (total, clients), not errors,
          errors[:3])
    check("each request's image is the same bytes for every client",
          all(len(bodies) == 1 for bodies in results.values()) and len(results) == len(REQUESTS),
          {q: len(b) for q, b in results.items()})

    # 2. Sliders moved at random for `seconds`.
    moved, moved_latencies, moved_errors = [0], [], []

    def slider_client(k):
        rng = random.Random(k)
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            sets = ["lights.0.position=[%.2f,%.2f,%.2f]" % (rng.uniform(-4, 4), rng.uniform(2, 6),
                                                          rng.uniform(-4, 4)),
                    "render.shadow_map.bias=%.5f" % rng.uniform(0, 0.05),
                    "render.shadow_map.resolution=%d" % rng.choice([64, 256, 1024]),
                    'render.shadows="%s"' % rng.choice(["map", "volume", "planar"])]
            query = "scene=shadows.json&engine=raster&width=160&height=100&client=slide%d&" % k
            query += "&".join("set=" + urllib.parse.quote(v, safe="") for v in sets)
            t0 = time.monotonic()
            status, body = get(port, query)
            with lock:
                moved[0] += 1
                moved_latencies.append(time.monotonic() - t0)
                if status != 200 or body[:8] != PNG:
                    moved_errors.append((query, status, body[:120]))

    start = time.monotonic()
    run_clients(clients, slider_client)
    report("sliders", moved_latencies, moved[0], time.monotonic() - start)
    check("%d clients moving sliders for %.0f s: every request answered with an image" %
          (clients, seconds), moved[0] > 0 and not moved_errors, moved_errors[:3])
    with open("/proc/%d/status" % server.pid) as f:
        peak = int(re.search(r"VmHWM:\s+(\d+) kB", f.read()).group(1)) * 1024
    print("the server's peak memory: %.0f MiB" % (peak / 2**20))
    check("the server's peak memory under %d MiB" % (MEMORY_BOUND >> 20), peak < MEMORY_BOUND, peak)
    check("the server still answers", get(port, REQUESTS[0])[0] == 200)
    check("the server is alive", server.poll() is None)

    # 3. A closed tab: the first frame of a long progressive render, then the client goes.
    tab = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    tab.request("GET", "/api/progressive?scene=cornell.json&engine=path&spp=4096&width=320&"
                "height=240")
    response = tab.getresponse()
    response.read(4)  # its first frame has come
    tab.sock.shutdown(socket.SHUT_RDWR)  # the tab is closed
    tab.close()
    # 4096 passes take about a minute: the render must end long before (/api/status counts
    # the renders in progress).
    ended = False
    for _ in range(100):
        with urllib.request.urlopen("http://127.0.0.1:%d/api/status" % port, timeout=30) as r:
            if json.loads(r.read())["renders"] == 0:
                ended = True
                break
        time.sleep(0.1)
    check("a closed tab's render ends", ended)
finally:
    server.terminate()
    server.wait(timeout=30)
    shutil.rmtree(served, ignore_errors=True)

print("%d failed" % len(failures) if failures else "all passed")
sys.exit(1 if failures else 0)
