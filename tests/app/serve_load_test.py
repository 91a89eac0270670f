"""svetlo serve under load (docs/viewer.md, "Under load"): twenty clients at once, each asking
for renders of several scenes and engines, so that requests share the server's mesh and BVH
caches and evict each other's entries. Every answer must be an image (200), every client's
image of the same request must be the same bytes (the caches change nothing), and the server
must still answer afterwards. Prints the latencies (median, 95th percentile, worst).

    serve_load_test.py SVETLO SCENES_DIR [CLIENTS [ROUNDS]]
"""
import re
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.request

svetlo, scenes = sys.argv[1], sys.argv[2]
clients = int(sys.argv[3]) if len(sys.argv) > 3 else 20
rounds = int(sys.argv[4]) if len(sys.argv) > 4 else 4

# Small films: the load, not the renders, is what is tested. Five scenes and the four
# engines; bunny.json's mesh and BVH are the large ones.
REQUESTS = [
    "scene=bunny.json&engine=path&spp=1&width=64&height=48",
    "scene=bunny.json&engine=whitted&spp=1&width=64&height=48",
    "scene=cornell.json&engine=path&spp=2&width=48&height=48",
    "scene=shadows.json&engine=raster&spp=1&width=96&height=60",
    "scene=spheres.json&engine=whitted&spp=1&width=64&height=40",
    "scene=cornell_radiosity.json&engine=radiosity&spp=1&width=32&height=32",
]

failures = []


def check(name, ok, detail=""):
    print(("ok   " if ok else "FAIL ") + name + ("" if ok else ": " + str(detail)))
    if not ok:
        failures.append(name)


def get(port, query):
    url = "http://127.0.0.1:%d/api/render?%s" % (port, query)
    try:
        with urllib.request.urlopen(url, timeout=120) as r:
            return r.status, r.read()
    except urllib.error.HTTPError as e:
        return e.code, e.read()


server = subprocess.Popen([svetlo, "serve", scenes, "--port", "0"], stderr=subprocess.PIPE,
                          text=True)
try:
    line = server.stderr.readline()
    m = re.match(r"svetlo: serving http://127\.0\.0\.1:(\d+)/$", line.strip())
    if not m:
        print("FAIL the server's line: " + line)
        sys.exit(1)
    port = int(m.group(1))
    results = {}  # request -> set of bodies
    latencies = []
    errors = []
    lock = threading.Lock()

    def client(k):
        for r in range(rounds):
            for j in range(len(REQUESTS)):
                query = REQUESTS[(j + k + r) % len(REQUESTS)]
                t0 = time.monotonic()
                status, body = get(port, query + "&client=load%d" % k)
                dt = time.monotonic() - t0
                with lock:
                    latencies.append(dt)
                    if status != 200 or body[:8] != b"\x89PNG\r\n\x1a\n":
                        errors.append((query, status, body[:120]))
                    else:
                        results.setdefault(query, set()).add(body)

    start = time.monotonic()
    threads = [threading.Thread(target=client, args=(k,)) for k in range(clients)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    wall = time.monotonic() - start
    total = clients * rounds * len(REQUESTS)
    check("%d requests from %d clients: every one an image" % (total, clients), not errors,
          errors[:3])
    check("each request's image is the same bytes for every client",
          all(len(bodies) == 1 for bodies in results.values()) and len(results) == len(REQUESTS),
          {q: len(b) for q, b in results.items()})
    check("the server still answers", get(port, REQUESTS[0])[0] == 200)
    check("the server is alive", server.poll() is None)
    latencies.sort()
    print("latency: median %.3f s, 95th percentile %.3f s, worst %.3f s; %d requests in %.1f s "
          "(%.1f a second)" % (latencies[len(latencies) // 2],
                               latencies[int(0.95 * (len(latencies) - 1))], latencies[-1],
                               total, wall, total / wall))
finally:
    server.terminate()
    server.wait(timeout=30)

print("%d failed" % len(failures) if failures else "all passed")
sys.exit(1 if failures else 0)
