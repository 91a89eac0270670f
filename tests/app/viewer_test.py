"""svetlo serve in a real browser (docs/viewer.md): Debian's chromium, headless, driven through
its DevTools protocol with Debian's python3-websocket. The page must show a non-blank image
in #view; switching the engine, the shading mode and the samples slider must change its
pixels and the query string; the query string must restore the same view in a new tab; the
console must stay free of errors. The HTTP API's refusals are checked too.

    viewer_test.py SVETLO SCENES_DIR [SCREENSHOT.png]
Exit 0 when every check passes; 77 (CTest's skip) when chromium or websocket is missing.
"""
import base64
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.parse
import urllib.request

# Under an emulator (make test-arm64: SVETLO_EMULATED=1) the server runs tens of times slower:
# every wait is that much longer there (viewer_page.SLOW). The checks themselves are the same.
from devtools import Tab, check, failures, first_page, start_chromium  # noqa: E402
from png_chunks import without_text  # noqa: E402
from viewer_page import SLOW, VIEW, set_control, settle, wait_view  # noqa: E402


def http(port, path):
    """The status and body of a GET; a PNG's body without its provenance (png_chunks.py), so
    that equal bodies mean equal images."""
    try:
        url = "http://127.0.0.1:%d%s" % (port, path)
        with urllib.request.urlopen(url, timeout=30 * SLOW) as r:
            return r.status, without_text(r.read())
    except urllib.error.HTTPError as e:
        return e.code, e.read()


def main():
    svetlo, scenes = sys.argv[1], sys.argv[2]
    screenshot = sys.argv[3] if len(sys.argv) > 3 else None
    server = subprocess.Popen([svetlo, "serve", scenes, "--port", "0"], stderr=subprocess.PIPE,
                              text=True)
    line = server.stderr.readline()
    m = re.match(r"svetlo: serving http://127\.0\.0\.1:(\d+)/$", line.strip())
    check("the line of docs/viewer.md", m is not None, line)
    if not m:
        server.kill()
        return 1
    port = int(m.group(1))
    profile = tempfile.mkdtemp(prefix="svetlo_chromium_")
    browser = None
    try:
        # The API: refusals with one line, and a PNG.
        status, body = http(port, "/api/render?scene=cornell.json&engine=raster&width=64&height=36")
        check("a render is a PNG", status == 200 and body[:8] == b"\x89PNG\r\n\x1a\n", status)
        for bad in ["../CMakeLists.txt", "..%2FREADME.md", "%2Fetc%2Fpasswd", ".hidden.json",
                    "cornell.json%00.json"]:
            status, body = http(port, "/api/render?scene=" + bad)
            check("refused: " + bad, status == 400 and body.count(b"\n") == 1, (status, body[:100]))
        status, body = http(port, "/api/render?scene=cornell.json&spp=0")
        check("a bad value gets 400 and one line", status == 400 and b"spp" in body, body)
        status, body = http(port, "/api/render?scene=cornell.json&set=render.shading%3D%22glow%22")
        check("a bad key's value gets the scene's message", status == 400 and b"render.shading" in body, body)
        status, body = http(port, "/api/render?scene=cornell.json&preview=2")
        check("a bad preview gets 400 and one line", status == 400 and b"preview" in body and
              body.count(b"\n") == 1, body)
        # preview=1 draws a light with area from its centre alone (raster.json's area light):
        # the same bytes as the still frame with one point set, and different from the still
        # frame; it changes nothing where there is none (shadows.json: a spot light).
        small = "&engine=raster&width=64&height=36&spp=1"
        one = "&set=render.area_light_points%3D1&set=render.area_shadow_points%3D1"
        for scene, differ in [("raster.json", True), ("shadows.json", False)]:
            still = http(port, "/api/render?scene=" + scene + small)
            moving = http(port, "/api/render?scene=" + scene + small + "&preview=1")
            check("preview=1 on " + scene + (" differs" if differ else " is the same"),
                  still[0] == 200 and moving[0] == 200 and (still[1] != moving[1]) == differ)
            check("preview=1 on " + scene + " is the still frame from one point",
                  http(port, "/api/render?scene=" + scene + small + one) == moving)
        check("the server keeps serving", http(port, "/api/scenes")[0] == 200)

        # A link's set= in the bare form of the contract (set=KEY=VALUE, '=' unescaped) is
        # read as --set reads it: the same image as the quoted, escaped form.
        small = "/api/render?scene=cornell.json&engine=raster&width=64&height=36"
        bare = http(port, small + "&set=render.shading=flat")
        quoted = http(port, small + "&set=render.shading%3D%22flat%22")
        check("a bare set= value renders", bare[0] == 200, bare)
        check("a bare set= value is read as --set reads it", bare == quoted)
        check("the bare and the scene's shading differ", bare[1] != http(port, small)[1])
        # Every file a scene names lies in the served folder, from an override too: a mesh, a
        # texture, an absolute path, a way up and out. Each a 400 naming the key, in one line
        # that names no path of the server's own.
        outside = tempfile.mkdtemp(prefix="svetlo_outside_")
        with open(os.path.join(outside, "tri.obj"), "w") as f:
            f.write("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
        shutil.copy(os.path.join(scenes, "textures", "grid.png"), os.path.join(outside, "photo.png"))
        folder = os.path.realpath(scenes)
        for key, value in [("objects.0.file", os.path.join(outside, "tri.obj")),
                           ("objects.0.file", "../tests/data/bad_index.obj"),
                           ("objects.0.file", "textures/../../README.md"),
                           ("materials.m.albedo", json.dumps({"texture": os.path.join(outside, "photo.png")})),
                           ("materials.m.albedo", json.dumps({"texture": "../../../etc/passwd"}))]:
            sets = "&set=" + urllib.parse.quote(key + "=" + value, safe="")
            if key.startswith("materials"):
                sets += "&set=" + urllib.parse.quote('materials.m.type="lambert"', safe="") + \
                        "&set=" + urllib.parse.quote("objects.0.material=m", safe="")
            status, body = http(port, small + sets)
            text = body.decode("utf-8", "replace")
            check("refused outside the folder: %s=%s" % (key, value),
                  status == 400 and body.count(b"\n") == 1 and "outside the served folder" in text
                  and ("objects[0].file" in text or "albedo.texture" in text), (status, text))
            check("the message names no path of the server's: %s" % value,
                  folder not in text, text)
        shutil.rmtree(outside, ignore_errors=True)
        status, body = http(port, "/api/render?scene=cornell.json&set=render.shading%3D%22glow%22")
        check("a scene's message names the scene relative to the folder",
              body.startswith(b"cornell.json: render.shading:"), body)
        # /api/link: the page's start, read by the server.
        status, body = http(port, "/api/link?scene=cornell.json&engine=raster&set=render.shading=phong"
                                  "&set=lights.0.intensity=[1,2,3]&set=camera.fov=30")
        link = json.loads(body)
        check("a link's values read as --set reads them",
              [s["value"] for s in link["sets"]] == ["phong", [1, 2, 3], 30] and "error" not in link, link)
        for query, named in [("scene=nothing.json&engine=raster", "nothing.json"),
                             ("scene=cornell.json&engine=warp", "warp"),
                             ("scene=cornell.json&set=oops", "oops"),
                             ("scene=cornell.json&spp=zero", "spp")]:
            link = json.loads(http(port, "/api/link?" + query)[1])
            check("a link's problem is named: " + query, named in link.get("error", ""), link)
        taken = subprocess.run([svetlo, "serve", scenes, "--port", str(port)], capture_output=True,
                               text=True, timeout=30 * SLOW)
        check("a port in use: one line naming --port", taken.returncode == 1 and
              taken.stderr.count("\n") == 1 and "--port" in taken.stderr, taken.stderr)

        url = "http://127.0.0.1:%d/?scene=shadows.json&engine=raster" % port
        browser, devtools = start_chromium(profile, url)
        check("chromium's DevTools", devtools is not None)
        if devtools is None:
            return 1
        tab = Tab(first_page(devtools), timeout=60 * SLOW)

        first = wait_view(tab)
        check("#view shows an image", first is not None)
        if first is None:
            return 1
        check("#view is not blank", first[1] > 100, first[1])
        views = [first]
        for element, value, event in [("shading", "flat", "change"), ("engine", "whitted", "change"),
                                      ("engine", "raster", "change"), ("spp", "0", "input")]:
            set_control(tab, element, value, event)
            v = wait_view(tab, views[-1][2])
            check("%s=%s changes the pixels" % (element, value), v is not None and v[0] != views[-1][0],
                  v and v[:2])
            if v:
                views.append(v)
        # The shadow map's bias slider (peter-panning at its top), then its depth map one
        # click away, then the image again.
        set_control(tab, "shadows", "map", "change")
        v = wait_view(tab, views[-1][2])
        if v:
            views.append(v)
        tab.eval("(() => { const e = document.querySelector('[data-key=\"render.shadow_map.bias\"]');"
                 " e.value = 100; e.dispatchEvent(new Event('input')); })()")
        v = wait_view(tab, views[-1][2])
        check("the shadow map's bias slider changes the pixels", v is not None and v[0] != views[-1][0],
              v and v[:2])
        if v:
            views.append(v)
        # The engine menus are the registry's engines (/api/engines), which say which stream
        # their passes; the page compares no engine names.
        engines = json.loads(http(port, "/api/engines")[1])
        check("/api/engines lists the four engines, path and radiosity showing their passes",
              [e["name"] for e in engines] == ["raster", "whitted", "path", "radiosity"] and
              [e["name"] for e in engines if e["shows_passes"]] == ["path", "radiosity"], engines)
        check("the engine menus are /api/engines'",
              tab.eval("[...document.getElementById('engine').options].map(o => o.value).join()") ==
              "raster,whitted,path,radiosity" and
              tab.eval("[...document.getElementById('bengine').options].map(o => o.value).join()") ==
              ",raster,whitted,path,radiosity")
        # The environment menu (the folder's maps), then its rotation slider, then none again.
        listed = json.loads(http(port, "/api/scenes")[1]).get("environments", [])
        check("/api/scenes lists the folder's maps", "references/door_ajar.exr" in listed, listed)
        set_control(tab, "environment", "references/door_ajar.exr", "change")
        v = wait_view(tab, views[-1][2])
        check("an environment from the menu changes the pixels", v is not None and
              v[0] != views[-1][0] and "environment" in tab.eval("location.search"), v and v[:2])
        if v:
            views.append(v)
        tab.eval("(() => { const e = document.querySelector('[data-key=\"environment.rotate\"]');"
                 " e.value = 90; e.dispatchEvent(new Event('input')); })()")
        v = wait_view(tab, views[-1][2])
        check("the environment's rotation slider changes the pixels",
              v is not None and v[0] != views[-1][0], v and v[:2])
        if v:
            views.append(v)
        set_control(tab, "environment", "", "change")
        v = wait_view(tab, views[-1][2])
        if v:
            views.append(v)
        for value in ["shadow_map", ""]:
            set_control(tab, "aov", value, "change")
            v = wait_view(tab, views[-1][2])
            check("buffer '%s' changes the pixels" % value, v is not None and v[0] != views[-1][0],
                  v and v[:2])
            if v:
                views.append(v)
            if value:
                check("the buffer is in the query string", "aov=" + value in tab.eval("location.search"))
        # A/B: B in Phong shading against A; their ꟻLIP difference, then the split view.
        set_control(tab, "bshading", "phong", "change")
        v = wait_view(tab, views[-1][2])
        if v:
            views.append(v)
        set_control(tab, "abview", "diff", "change")
        v = wait_view(tab, views[-1][2])
        check("the A/B difference shows ꟻLIP's error", v is not None and v[0] != views[-1][0] and
              "ꟻLIP" in tab.eval("document.getElementById('status').textContent"), v and v[:2])
        if v:
            views.append(v)
        set_control(tab, "abview", "split", "change")
        v = wait_view(tab, views[-1][2])
        shown_b = tab.eval("(() => { const b = document.getElementById('view-b');"
                           " return !b.classList.contains('hidden') && b.src.startsWith('data:image/png')"
                           " && b.complete && b.naturalWidth > 0; })()")
        check("the split view shows B over A", v is not None and shown_b, (v and v[:2], shown_b))
        if v:
            views.append(v)
        check("A/B is in the query string", "ab=split" in tab.eval("location.search") and
              "b_set=" in tab.eval("location.search"))
        set_control(tab, "abview", "", "change")
        v = wait_view(tab, views[-1][2])
        if v:
            views.append(v)
        # Progressive display: the path tracer at 32 spp shows its passes as they come.
        set_control(tab, "spp", "5", "input")
        set_control(tab, "engine", "path", "change")
        seen, end = [], time.time() + 120 * SLOW
        while time.time() < end:
            text = tab.eval("document.getElementById('status').textContent")
            m = re.match(r"path tracing, (\d+) spp, .*(refining|done)", text or "")
            if m and (not seen or seen[-1] != (int(m.group(1)), m.group(2))):
                seen.append((int(m.group(1)), m.group(2)))
            if m and m.group(2) == "done" and not tab.eval("window.svetloBusy()"):
                break
            time.sleep(0.02)
        check("the path tracer's passes show as they come, to 32 spp",
              len(seen) >= 3 and seen[-1] == (32, "done") and
              all(a[0] <= b[0] for a, b in zip(seen, seen[1:])), seen)
        v = wait_view(tab, views[-1][2])
        if v:
            views.append(v)
        set_control(tab, "engine", "raster", "change")
        set_control(tab, "spp", "0", "input")
        v = wait_view(tab, views[-1][2])
        if v:
            views.append(v)
        final = settle(tab)
        search = tab.eval("location.search")
        check("the controls write the query string",
              "engine=raster" in search and "render.shading" in search and "spp=1" in search and
              "render.shadow_map.bias" in search, search)
        command = tab.eval("document.getElementById('command').textContent")
        check("the command line of the view", command.startswith("svetlo render shadows.json"), command)

        # A new tab at the same address shows the same pixels.
        href = tab.eval("location.href")
        req = urllib.request.Request("http://127.0.0.1:%d/json/new?%s"
                                     % (devtools, urllib.parse.quote(href, safe="")), method="PUT")
        target = json.loads(urllib.request.urlopen(req, timeout=30 * SLOW).read())
        again = Tab(target["webSocketDebuggerUrl"], timeout=60 * SLOW)
        restored = settle(again)
        check("the query string restores the view",
              restored is not None and final is not None and restored[0] == final[0],
              (restored and restored[:2], final and final[:2], href, again.eval("location.href")))
        # The contract's links in the bare form, each in a new tab: the view it names, or the
        # page with its one-line error (never a blank page, never an exception).
        def open_tab(query):
            req = urllib.request.Request("http://127.0.0.1:%d/json/new?%s" % (
                devtools, urllib.parse.quote("http://127.0.0.1:%d/?%s" % (port, query), safe="")),
                method="PUT")
            return Tab(json.loads(urllib.request.urlopen(req, timeout=30 * SLOW).read())["webSocketDebuggerUrl"],
                       timeout=60 * SLOW)
        shared = open_tab("scene=cornell.json&engine=raster&set=render.shading=phong&set=camera.fov=30")
        shown = settle(shared)
        check("a bare-value link shows its view", shown is not None and shown[1] > 100, shown and shown[:2])
        check("a bare-value link sets its controls",
              shared.eval("document.getElementById('shading').value") == "phong" and
              "camera.fov=30" in shared.eval("document.getElementById('sets').value"),
              shared.eval("location.search"))
        check("a bare-value link: no error", not shared.errors and
              not shared.eval("document.getElementById('error').textContent"), shared.errors)
        for query, named in [("scene=nothing.json&engine=raster", "nothing.json"),
                             ("scene=cornell.json&engine=warp", "warp")]:
            broken = open_tab(query)
            end, text = time.time() + 30 * SLOW, ""
            while time.time() < end and not text:
                text = broken.eval("document.getElementById('error').textContent") or ""
                time.sleep(0.1)
            check("a link naming %s shows the page and its error" % named,
                  named in text and broken.eval("document.getElementById('scene').options.length") > 0
                  and not broken.errors, (text, broken.errors))
        if screenshot:
            shot = tab.call("Page.captureScreenshot", format="png")
            with open(screenshot, "wb") as f:
                f.write(base64.b64decode(shot["data"]))
        check("no error in the console", not tab.errors and not again.errors, tab.errors + again.errors)
    finally:
        if browser:
            browser.kill()
        server.kill()
        shutil.rmtree(profile, ignore_errors=True)
    print("%d failed" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
