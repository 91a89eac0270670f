"""The browser's speed against the native program's (docs/web.md, "Speed"): the same render
(path, scenes/cornell.json, 128 x 128, 32 spp) in build/web's page in headless chromium, on one
thread and on two, and `svetlo render` natively on one and two, side by side, best of 3 each.

    /usr/bin/python3 bench/web_speed.py build/svetlo build/web scenes
"""
import json
import os
import re
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "app"))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "web"))
import devtools  # noqa: E402
import web_test as W  # noqa: E402


def main():
    svetlo, web, scenes = sys.argv[1:4]
    server = subprocess.Popen([sys.executable, os.path.join(os.path.dirname(W.__file__),
                                                            "static_server.py"), web, "0",
                               "--isolated"], stdout=subprocess.PIPE, text=True)
    port = int(re.search(r"serving on (\d+)", server.stdout.readline()).group(1))
    profile = tempfile.mkdtemp()
    browser, port_devtools = devtools.start_chromium(profile, "about:blank")
    try:
        tab = devtools.Tab(devtools.first_page(port_devtools), timeout=300)
        tab.call("Page.navigate", url="http://127.0.0.1:%d/index.html?engine=raster&spp=1" % port)
        while tab.eval("typeof svetlo !== 'undefined' ? svetlo.ready.then(() => true) : null") is not True:
            time.sleep(0.1)
        rows = []
        for threads in (1, 2):
            opts = {"engine": "path", "width": 128, "height": 128, "spp": 32, "seed": 1,
                    "threads": threads}
            web_s = min(tab.eval(W.RENDER % ('"cornell.json"', json.dumps(opts)))["seconds"]
                        for _ in range(3))
            native_s = []
            for _ in range(3):
                out = subprocess.run([svetlo, "render", os.path.join(scenes, "cornell.json"), "-e",
                                      "path", "-W", "128", "-H", "128", "--spp", "32", "--seed",
                                      "1", "-t", str(threads), "-o", os.path.join(profile, "n.pfm")],
                                     capture_output=True, text=True, check=True)
                m = re.search(r"setup ([\d.]+) s, render ([\d.]+) s", out.stderr)
                native_s.append(float(m.group(1)) + float(m.group(2)))  # as svetlo.render's seconds
            rows.append((threads, web_s, min(native_s)))
        print("| threads | browser (s) | native (s) | browser / native |")
        print("| --- | --- | --- | --- |")
        for threads, web_s, native_s in rows:
            print("| %d | %.3f | %.3f | %.2f |" % (threads, web_s, native_s, web_s / native_s))
        print("browser: two threads are %.2f x one" % (rows[0][1] / rows[1][1]))
    finally:
        browser.kill()
        server.kill()


if __name__ == "__main__":
    main()
