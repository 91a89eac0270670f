"""svetlo serve's speed (docs/viewer.md, "Measured"): the round trip of the requests the page
sends, from the client's clock, with the server's render and encoder seconds
(X-Svetlo-Seconds, X-Svetlo-Encode-Seconds) and the bytes sent, median of 8 after one to
warm up; the first frame of a progressive path render; and a drag of the camera over
scenes/raster.json, as the page sends it (one request at a time, each the next step of an
orbit, JPEG, preview=1), over one kept-alive connection as the browser sends it and over
a new connection each.

    /usr/bin/python3 bench/serve_latency.py SVETLO [SCENES_DIR] [--against OTHER [--pairs N]]

With --against, OTHER and SVETLO are measured in turn, N times each (on a machine whose speed
wanders within a run, only programs measured side by side compare).
"""
import argparse
import http.client
import math
import re
import statistics
import struct
import subprocess
import time
import urllib.parse
import urllib.request

parser = argparse.ArgumentParser()
parser.add_argument("svetlo")
parser.add_argument("scenes", nargs="?", default="scenes")
parser.add_argument("--against", help="another svetlo, measured in turn with the first")
parser.add_argument("--pairs", type=int, default=3, help="turns of each, with --against")
args = parser.parse_args()
scenes = args.scenes
MAP = "&set=render.shadows%3D%22map%22"
REQUESTS = [
    ("raster 960 x 540, shadows.json, shadow map, 1 spp", "png",
     "render?scene=shadows.json&engine=raster&spp=1&width=960&height=540" + MAP),
    ("the same", "jpeg",
     "render?scene=shadows.json&engine=raster&spp=1&width=960&height=540&format=jpeg" + MAP),
    ("path 480 x 270, cornell.json, first pass", "jpeg",
     "render?scene=cornell.json&engine=path&spp=1&width=480&height=270&format=jpeg"),
]


def measure(svetlo):
    server = subprocess.Popen([svetlo, "serve", scenes, "--port", "0"], stderr=subprocess.PIPE,
                              text=True)
    try:
        port = int(re.search(r":(\d+)/", server.stderr.readline()).group(1))
        base = "http://127.0.0.1:%d/api/" % port
        print("| request | format | round trip | render | encoder | bytes |")
        print("|---|---|---|---|---|---|")
        for name, fmt, path in REQUESTS:
            trips, renders, encoders, size = [], [], [], 0
            for k in range(9):
                t0 = time.perf_counter()
                with urllib.request.urlopen(base + path, timeout=60) as r:
                    body = r.read()
                    trip = time.perf_counter() - t0
                    if k == 0:
                        continue
                    trips.append(trip)
                    renders.append(float(r.headers["X-Svetlo-Seconds"]))
                    encoders.append(float(r.headers["X-Svetlo-Encode-Seconds"]))
                    size = len(body)
            print("| %s | %s | %.1f ms | %.1f ms | %.1f ms | %d KiB |" % (
                name, fmt.upper(), 1000 * statistics.median(trips), 1000 * statistics.median(renders),
                1000 * statistics.median(encoders), size // 1024))
        firsts = []
        for k in range(9):
            t0 = time.perf_counter()
            r = urllib.request.urlopen(base + "progressive?scene=cornell.json&engine=path&spp=64&"
                                       "width=480&height=270&client=bench", timeout=60)
            header = struct.unpack(">I", r.read(4))[0]
            r.read(header)
            r.read(struct.unpack(">I", r.read(4))[0])
            if k > 0:
                firsts.append(time.perf_counter() - t0)
            r.close()
            time.sleep(0.5)  # the next request supersedes this one (same client)
        print("progressive path 480 x 270: first frame after %.1f ms (median of 8)" %
              (1000 * statistics.median(firsts)))
        # A drag: 61 frames of an orbit about raster.json's look_at (0, 0.6, 0), radius and height
        # of its camera, one request after the other, the first to warm up; over one kept-alive
        # connection, as the browser sends them, and over a new connection each.
        def drag(preview, frames, kept_alive):
            connection = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
            renders, encoders, sizes = [], [], []
            t_start = None
            for k in range(frames):
                a = 0.02 * k
                position = "[%.4f,2.2,%.4f]" % (6.5 * math.sin(a), 6.5 * math.cos(a))
                path = ("/api/render?scene=raster.json&engine=raster&spp=1&width=960&height=540"
                        "&format=jpeg&client=drag&preview=%s&set=camera.position%%3D%s" %
                        (preview, urllib.parse.quote(position)))
                connection.request("GET", path)
                r = connection.getresponse()
                body = r.read()
                if not kept_alive:
                    connection.close()
                if k == 0:
                    t_start = time.perf_counter()
                    continue
                renders.append(float(r.getheader("X-Svetlo-Seconds")))
                encoders.append(float(r.getheader("X-Svetlo-Encode-Seconds")))
                sizes.append(len(body))
            connection.close()
            per_frame = (time.perf_counter() - t_start) / (frames - 1)
            print("drag over raster.json 960 x 540, 1 spp, JPEG, preview=%s, %s: %.1f frames/s "
                  "(%.1f ms a frame: render %.1f ms, encoder %.1f ms, %.0f %% of the frame; %d KiB "
                  "a frame; %d frames)" % (
                      preview, "kept alive" if kept_alive else "a connection each",
                      1 / per_frame, 1000 * per_frame, 1000 * statistics.median(renders),
                      1000 * statistics.median(encoders),
                      100 * statistics.median(encoders) / per_frame,
                      statistics.median(sizes) // 1024, frames - 1))

        drag("1", 61, True)
        drag("1", 61, False)
        drag("0", 7, True)
    finally:
        server.terminate()
        server.wait(timeout=30)


if args.against:
    for _ in range(args.pairs):
        for program in (args.against, args.svetlo):
            print("== %s" % program, flush=True)
            measure(program)
else:
    measure(args.svetlo)
