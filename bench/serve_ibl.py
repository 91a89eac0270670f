"""svetlo serve's raster frames under image-based lighting (docs/performance.md, "Image-based
lighting in the viewer"): a drag of the camera about a glTF model lit by an environment map, as
the page sends it (one request at a time over a kept-alive connection, 960 x 540, JPEG), with
and without preview=1; frames a second from the client's clock, and the server's render time.

    /usr/bin/python3 bench/serve_ibl.py SVETLO FOLDER MODEL ENVIRONMENT [RADIUS HEIGHT]

FOLDER holds MODEL and ENVIRONMENT (the viewer serves the files of one folder), e.g. a copy of
../shared/data/gltf/FlightHelmet with ../shared/data/hdr/studio.exr beside FlightHelmet.gltf.
"""
import http.client
import math
import re
import statistics
import subprocess
import sys
import time
import urllib.parse

svetlo, folder, model, environment = sys.argv[1:5]
radius = float(sys.argv[5]) if len(sys.argv) > 5 else 1.1
height = float(sys.argv[6]) if len(sys.argv) > 6 else 0.45
server = subprocess.Popen([svetlo, "serve", folder, "--port", "0"], stderr=subprocess.PIPE,
                          text=True)
port = int(re.search(r":(\d+)/", server.stderr.readline()).group(1))
try:
    for preview in ("1", "0"):
        connection = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
        renders, frames, start = [], 31, None
        for k in range(frames):
            a = 0.03 * k  # an orbit about the model, the first frame to warm up
            position = "[%.4f,%.4f,%.4f]" % (radius * math.sin(a), height, radius * math.cos(a))
            path = ("/api/render?scene=%s&engine=raster&spp=1&width=960&height=540&format=jpeg"
                    "&client=drag&preview=%s&set=environment%%3D%s&set=camera.position%%3D%s" % (
                        urllib.parse.quote(model), preview,
                        urllib.parse.quote(f'{{"file":"{environment}"}}'),
                        urllib.parse.quote(position)))
            connection.request("GET", path)
            response = connection.getresponse()
            body = response.read()
            if response.status != 200:
                sys.exit("%d: %s" % (response.status, body.decode(errors="replace")))
            if k == 0:
                start = time.perf_counter()
                continue
            renders.append(float(response.getheader("X-Svetlo-Seconds")))
        per_frame = (time.perf_counter() - start) / (frames - 1)
        print("%s under %s, raster 960 x 540, JPEG, preview=%s: %.1f frames/s (%.1f ms a frame, "
              "render %.1f ms, median of %d)" % (model, environment, preview, 1 / per_frame,
                                                 1000 * per_frame, 1000 * statistics.median(renders),
                                                 frames - 1))
finally:
    server.terminate()
    server.wait(timeout=30)
