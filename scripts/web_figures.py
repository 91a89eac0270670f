"""The pictures of docs/web.md: the web page (build/web, make web) in Debian's headless
chromium, cross-origin isolated, as a visitor sees it:
  - web_page.png: cornell.json by the path tracer, 16 samples a pixel, A | B split against
    the rasterizer;
  - web_visitor_model.png: DamagedHelmet.glb chosen in the page's file input, by the path
    tracer.

    /usr/bin/python3 scripts/web_figures.py [WEB_DIR] [MODEL] [OUT_DIR]
(defaults: build/web, ../shared/data/gltf/DamagedHelmet/DamagedHelmet.glb, docs/images)."""
import base64
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "app"))

from devtools import Tab, first_page, start_chromium  # noqa: E402
from viewer_page import settle  # noqa: E402


def shoot(tab, path):
    with open(path, "wb") as f:
        f.write(base64.b64decode(tab.call("Page.captureScreenshot", format="png")["data"]))
    print("wrote", path)


def main():
    root = os.path.join(HERE, "..")
    web = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build", "web")
    model = sys.argv[2] if len(sys.argv) > 2 else os.path.join(
        root, "..", "shared", "data", "gltf", "DamagedHelmet", "DamagedHelmet.glb")
    out = sys.argv[3] if len(sys.argv) > 3 else os.path.join(root, "docs", "images")
    server = subprocess.Popen([sys.executable, os.path.join(root, "tests", "web", "static_server.py"),
                               web, "0", "--isolated"], stdout=subprocess.PIPE, text=True)
    port = int(re.search(r"serving on (\d+)", server.stdout.readline()).group(1))
    profile = tempfile.mkdtemp(prefix="svetlo_figures_")
    browser, devtools = start_chromium(profile, "about:blank", window="1000,640")
    try:
        tab = Tab(first_page(devtools), timeout=600)
        tab.call("Page.navigate", url="http://127.0.0.1:%d/index.html?scene=cornell.json"
                 "&engine=path&spp=16&ab=split&b_engine=raster" % port)
        time.sleep(1)
        if not settle(tab, 600):
            sys.exit("web_figures: the page showed no image")
        shoot(tab, os.path.join(out, "web_page.png"))
        element = tab.call("Runtime.evaluate", expression="document.getElementById('file')")
        tab.call("DOM.setFileInputFiles", objectId=element["result"]["objectId"],
                 files=[os.path.abspath(model)])
        name = os.path.basename(model)
        end = time.time() + 120
        while time.time() < end and tab.eval("document.getElementById('scene').value") != name:
            time.sleep(0.2)
        tab.eval("(() => { const e = document.getElementById('abview'); e.value = '';"
                 "e.dispatchEvent(new Event('change')); })()")
        time.sleep(1)
        if not settle(tab, 600):
            sys.exit("web_figures: the model showed no image")
        shoot(tab, os.path.join(out, "web_visitor_model.png"))
    finally:
        browser.kill()
        server.kill()
        shutil.rmtree(profile, ignore_errors=True)


if __name__ == "__main__":
    main()
