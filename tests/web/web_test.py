"""svetlo's web page (make web, docs/web.md) in Debian's headless chromium, driven through its
DevTools protocol as the viewer's test is, served by a static server with the headers of
cross-origin isolation. The page is svetlo serve's viewer (apps/svetlo/viewer/), its requests
answered in the page by the module:
  - the page loads, `svetlo.ready` settles, and #view shows an image; then one for each engine;
  - a shared link restores its view: the engine, the shading, the samples and the other keys;
  - each engine renders a bundled scene in the page, and its pixels are the native program's
    (`svetlo render` of the same scene, seed and spp) up to the last bits of the maths
    libraries (a relative RMS difference of at most 1e-6);
  - one thread and two give the same pixels, and two threads are faster;
  - served without the headers of isolation, the page runs its single-threaded module, and
    its pixels are the same;
  - a bad scene rejects svetlo.render with the one-line error, and the page renders after it;
  - a film past the WebAssembly memory's limit is refused with the one-line error;
  - a link's bare set= value is read as --set reads it;
  - a progressive render reports each pass; svetlo.cancel and any change of the page's controls
    end a render after its pass, and without isolation at once (a new worker); a render that
    reads no flag for a second is ended by a new worker, and the render asked after it follows;
  - the visitor's own files: a glTF given to svetlo.addFiles renders the native program's
    image; an OBJ and its MTL chosen in the page's file input render in #view;
  - a scene that the viewer cannot render shows its one-line error, and the page goes on;
  - the page makes no request outside its own origin, and logs no error.

    web_test.py SVETLO WEB_DIR SCENES_DIR
Exit 0 when every check passes; 77 (CTest's skip) when chromium or websocket is missing.
"""
import base64
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "app"))

from devtools import Tab, check, failures, first_page, start_chromium  # noqa: E402
from viewer_page import VIEW, set_control, settle  # noqa: E402


# svetlo.render's result as {width, height, seconds, b64 (the float32 pixels)}, or {error}.
RENDER = """svetlo.render(%s, %s).then(r => {
  const bytes = new Uint8Array(r.pixels.buffer, r.pixels.byteOffset, r.pixels.byteLength);
  let s = ''; for (let i = 0; i < bytes.length; i += 8192)
    s += String.fromCharCode.apply(null, bytes.subarray(i, i + 8192));
  return {width: r.width, height: r.height, seconds: r.seconds, b64: btoa(s)};
}, e => ({error: e.message}))"""

def floats(result):
    data = base64.b64decode(result["b64"])
    return struct.unpack("<%df" % (len(data) // 4), data)


def read_pfm(path):
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        rows = [struct.unpack(("<" if scale < 0 else ">") + "%df" % (3 * w), f.read(12 * w))
                for _ in range(h)]
    return w, h, [v for row in reversed(rows) for v in row]  # PFM stores the bottom row first


def relative_difference(a, b):
    """The RMS of a - b over the RMS of b."""
    num = sum((x - y) ** 2 for x, y in zip(a, b))
    den = sum(y * y for y in b)
    return (num / max(den, 1e-30)) ** 0.5


def change_ends_render(tab, where):
    """A change of the viewer's controls during a long render ends it: the path tracer's 256
    samples a pixel at 480 x 270 give way to one, within a pass where the page is isolated
    (the module's cancel flag), within the module's new start elsewhere (a new worker)."""
    set_control(tab, "engine", "path")
    set_control(tab, "spp", "8", "input")
    refining, end = None, time.time() + 60
    while time.time() < end and not refining:
        refining = re.search(r"(\d+) spp, ([\d.]+) s, refining",
                             tab.eval("document.getElementById('status').textContent") or "")
        time.sleep(0.02)
    check(where + "the path tracer shows its passes as they come", bool(refining))
    changed = time.time()
    set_control(tab, "spp", "0", "input")
    done = None
    while time.time() - changed < 60 and not done:
        done = tab.eval("!window.svetloBusy() && !document.getElementById('status')"
                        ".textContent.includes('refining') ? true : null")
        time.sleep(0.02)
    took = time.time() - changed
    if refining:
        per_pass = float(refining.group(2)) / int(refining.group(1))
        # Isolated: within a pass; elsewhere the new worker's start (about a second) too.
        allowed = 1.0 + 3 * per_pass + (0 if tab.eval("self.crossOriginIsolated") else 3.0)
        check(where + "a change ends the render in progress (%.2f s; a pass %.2f s, the whole "
              "render about %.0f s)" % (took, per_pass, 256 * per_pass),
              bool(done) and took < allowed and 256 * per_pass > 4 * took)
    set_control(tab, "engine", "raster")
    settle(tab)


def main():
    svetlo, web, scenes = sys.argv[1], sys.argv[2], sys.argv[3]
    work = tempfile.mkdtemp(prefix="svetlo_web_")
    server = subprocess.Popen([sys.executable, os.path.join(HERE, "static_server.py"), web, "0",
                               "--isolated"], stdout=subprocess.PIPE, text=True)
    port = int(re.search(r"serving on (\d+)", server.stdout.readline()).group(1))
    origin = "http://127.0.0.1:%d/" % port
    profile = tempfile.mkdtemp(prefix="svetlo_chromium_")
    url = origin + ("index.html?scene=cornell.json&engine=raster&spp=1&set=render.shading=phong"
                    "&set=camera.fov=45")
    browser, devtools = start_chromium(profile, "about:blank", window="1000,700")
    try:
        check("chromium's DevTools", devtools is not None)
        if devtools is None:
            return 1
        tab = Tab(first_page(devtools), timeout=300)
        start = time.time()
        tab.call("Page.navigate", url=url)
        ready = None
        while time.time() - start < 120:
            ready = tab.eval("typeof svetlo !== 'undefined' ? svetlo.ready.then(() => true, e => e.message) : null")
            if ready is not None:
                break
            time.sleep(0.1)
        check("svetlo.ready settles", ready is True, ready)
        if ready is not True:
            print("\n".join(tab.console + tab.errors))
            return 1
        check("the page is cross-origin isolated", tab.eval("self.crossOriginIsolated") is True)
        first = None
        while time.time() - start < 120 and not first:
            first = tab.eval(VIEW)
            time.sleep(0.05)
        print("first image in #view %.2f s after opening" % (time.time() - start))
        check("#view shows an image", bool(first) and first[1] > 100, first)
        # The link's view: its engine and shading in their menus, its other keys as --set
        # reads them, and no error.
        restored = tab.eval("""(() => { const $ = (id) => document.getElementById(id);
            return [$('engine').value, $('shading').value, $('sets').value, $('error').textContent];
            })()""")
        check("the link restores its view (engine, shading, other keys; no error)",
              restored == ["raster", "phong", "camera.fov=45", ""], restored)
        check("the page says it renders on the machine's threads",
              "threads" in (tab.eval("document.getElementById('threads').textContent") or ""))

        # #view shows an image for each engine, chosen in the page's menu.
        for engine in ("whitted", "path", "radiosity", "raster"):
            set_control(tab, "engine", engine)
            v = settle(tab)
            error = tab.eval("document.getElementById('error').textContent")
            check("#view shows %s's image" % engine, bool(v) and v[1] > 100 and error == "",
                  (v and v[1], error))

        change_ends_render(tab, "")

        # Each engine against the native program.
        # Measured: 1e-8 to 1e-7 (raster 7.4e-9, whitted 1.9e-8, path 9.6e-8, radiosity 5.9e-8).
        cases = [("raster", "cornell.json", 1e-6), ("whitted", "cornell.json", 1e-6),
                 ("path", "cornell.json", 1e-6), ("radiosity", "cornell_radiosity.json", 1e-6)]
        isolated_pixels = {}
        for engine, scene, tolerance in cases:
            opts = {"engine": engine, "width": 64, "height": 48, "spp": 4, "seed": 3, "threads": 2}
            r = tab.eval(RENDER % (json.dumps(scene), json.dumps(opts)))
            if not r or "error" in r or "b64" not in r:
                check("%s renders in the page" % engine, False, r)
                continue
            page = floats(r)
            native_file = os.path.join(work, engine + ".pfm")
            subprocess.run([svetlo, "render", os.path.join(scenes, scene), "-e", engine,
                            "-W", "64", "-H", "48", "--spp", "4", "--seed", "3", "-q", "-o",
                            native_file], check=True)
            w, h, native = read_pfm(native_file)
            check("%s renders in the page (%d x %d, %.2f s)" % (engine, r["width"], r["height"],
                                                                r["seconds"]),
                  (r["width"], r["height"]) == (w, h) and len(page) == len(native))
            diff = relative_difference(page, native)
            check("%s: the native program's image (relative RMS difference %.2e)" % (engine, diff),
                  diff <= tolerance, diff)
            isolated_pixels[engine] = (scene, opts, r["b64"])
            if engine == "path":
                one = tab.eval(RENDER % (json.dumps(scene), json.dumps(dict(opts, threads=1))))
                check("path: one thread and two give the same pixels",
                      one and one.get("b64") == r["b64"])

        # With the headers of isolation two threads beat one (on a machine with two cores):
        # the best of two renders each, 128 x 128 x 16 of the path tracer.
        if (tab.eval("navigator.hardwareConcurrency") or 1) >= 2:
            best = {}
            for threads in (1, 2):
                opts = {"engine": "path", "width": 128, "height": 128, "spp": 16, "seed": 1,
                        "threads": threads}
                runs = [tab.eval(RENDER % ('"cornell.json"', json.dumps(opts))) for _ in range(2)]
                best[threads] = min(r["seconds"] for r in runs if r and "seconds" in r)
            check("two threads beat one (%.2f s against %.2f s)" % (best[2], best[1]),
                  best[2] < best[1])

        # A bad scene: the one-line error, and the page still renders.
        bad = tab.eval(RENDER % (json.dumps({"film": {"width": -3}}), "{}"))
        check("a bad scene rejects with the one-line error",
              bad and "error" in bad and "\n" not in bad["error"] and "scene.json" in bad["error"],
              bad)
        bad_key = tab.eval(RENDER % (json.dumps("cornell.json"), json.dumps({"spp": 0})))
        check("a bad option names its key", bad_key and "spp" in bad_key.get("error", ""), bad_key)
        # A film past the WebAssembly memory's limit: refused with the one-line error, and the
        # page goes on (the same request would crash the tab).
        huge = tab.eval(RENDER % (json.dumps("cornell.json"),
                                  json.dumps({"engine": "path", "width": 8192, "height": 8192,
                                              "spp": 1})))
        check("a render past the memory limit is refused with the one-line error",
              huge and "\n" not in huge.get("error", "\n") and
              "cornell.json: film: a 8192 x 8192 render in path needs about" in huge["error"],
              huge)
        after = tab.eval(RENDER % (json.dumps("cornell.json"),
                                   json.dumps({"engine": "raster", "width": 32, "height": 32})))
        check("the page renders after an error", after and "b64" in after, after)

        # Each pass as it comes, and a render ended after its pass.
        passes = tab.eval("""(() => { let n = 0; return svetlo.render('cornell.json',
            {engine: 'path', width: 32, height: 24, spp: 6, onPass: () => n++})
            .then(r => ({n, passes: r.passes, cancelled: r.cancelled}),
                  e => ({error: e.message})); })()""")
        check("onPass is called after each pass of the path tracer",
              passes == {"n": 6, "passes": 6, "cancelled": False}, passes)
        ended = tab.eval("""new Promise(resolve => { let first = null;
            svetlo.render('cornell.json', {engine: 'path', width: 64, height: 48, spp: 1000000,
                onPass: () => { if (first === null) { first = performance.now();
                                                      svetlo.cancel(); } }})
            .then(r => resolve({passes: r.passes, cancelled: r.cancelled,
                                ms: performance.now() - first}),
                  e => resolve({error: e.message})); })""")
        check("svetlo.cancel ends a render after its pass (%s)" % ended,
              bool(ended) and ended.get("cancelled") is True and ended.get("passes", 1e9) <= 3
              and ended.get("ms", 1e9) < 5000, ended)

        # A render that never reads the flag (one long pass of the rasterizer: 256 samples a
        # pixel at 480 x 270, minutes in the page) ends within the grace of a second, by a new
        # worker; the render asked after it is rendered by that one.
        grace = tab.eval("""new Promise(resolve => { const t0 = performance.now();
            const a = svetlo.render('cornell.json', {engine: 'raster', width: 480, height: 270,
                                                     spp: 256});
            const b = svetlo.render('cornell.json', {engine: 'raster', width: 32, height: 32});
            setTimeout(() => svetlo.cancel(), 300);
            Promise.all([a, b]).then(([x, y]) => resolve({cancelled: x.cancelled,
                ms: performance.now() - t0, after: y.pixels.length, after_cancelled: y.cancelled}),
                e => resolve({error: e.message})); })""")
        check("svetlo.cancel ends a long raster pass within its grace, and the next render "
              "follows (%s)" % grace,
              bool(grace) and grace.get("cancelled") is True and grace.get("ms", 1e9) < 3000
              and grace.get("after") == 32 * 32 * 3 and grace.get("after_cancelled") is False,
              grace)

        # The visitor's own files: a glTF through svetlo.addFiles, against the native program.
        data = os.path.join(HERE, "..", "data")
        model = os.path.join(data, "triangle.gltf")
        with open(model, "rb") as f:
            b64 = base64.b64encode(f.read()).decode()
        names = tab.eval("svetlo.addFiles([{name: 'models/../triangle.gltf', bytes: "
                         "Uint8Array.from(atob(%s), c => c.charCodeAt(0))}])"
                         ".then(n => n, e => ({error: e.message}))" % json.dumps(b64))
        check("svetlo.addFiles keeps a file's own name, without folders",
              names == ["triangle.gltf"], names)
        refused = tab.eval("svetlo.addFiles([{name: 'models/..', bytes: new Uint8Array(4)}])"
                           ".then(n => n, e => ({error: e.message}))")
        check("svetlo.addFiles refuses a name that is no file's with the one-line error",
              refused == {"error": "models/..: addFiles: not a file's name"}, refused)
        opts = {"engine": "raster", "width": 64, "height": 48, "spp": 4, "seed": 3}
        r = tab.eval(RENDER % (json.dumps("triangle.gltf"), json.dumps(opts)))
        native_file = os.path.join(work, "visitor.pfm")
        subprocess.run([svetlo, "render", model, "-e", "raster", "-W", "64", "-H", "48", "--spp",
                        "4", "--seed", "3", "-q", "-o", native_file], check=True)
        w, h, native = read_pfm(native_file)
        ok = bool(r) and "b64" in r and (r["width"], r["height"]) == (w, h)
        diff = relative_difference(floats(r), native) if ok else None
        opts_visitor, visitor_native = opts, native
        check("a visitor's glTF: the native program's image (relative RMS difference %s)" %
              ("%.2e" % diff if ok else "-"), ok and diff <= 1e-6, r and r.get("error"))
        # An OBJ and its MTL as a visitor chooses them in the page's file input.
        element = tab.call("Runtime.evaluate", expression="document.getElementById('file')")
        tab.call("DOM.setFileInputFiles", objectId=element["result"]["objectId"],
                 files=[os.path.abspath(os.path.join(scenes, "models", name))
                        for name in ("CornellBox-Original.obj", "CornellBox-Original.mtl")])
        chosen, lit = None, None
        end = time.time() + 120
        while time.time() < end and not (chosen == "CornellBox-Original.obj" and lit):
            time.sleep(0.1)
            chosen = tab.eval("document.getElementById('scene').value")
            lit = settle(tab)
        check("a visitor's OBJ and MTL chosen in the page render in #view",
              chosen == "CornellBox-Original.obj" and bool(lit) and lit[1] > 100 and
              tab.eval("document.getElementById('error').textContent") == "",
              (chosen, lit, tab.eval("document.getElementById('error').textContent")))

        # A visitor's glTF whose base colour is an image file beside it, both through
        # svetlo.addFiles: the native program's image (the page read no image files before).
        with open(model) as f:
            textured = json.load(f)
        textured["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]
        textured["textures"] = [{"source": 0}]
        textured["images"] = [{"uri": "red_texture.png"}]
        for mesh in textured["meshes"]:
            for prim in mesh["primitives"]:
                prim["material"] = 0
        textured_file = os.path.join(work, "textured.gltf")
        with open(textured_file, "w") as f:
            json.dump(textured, f)
        red = b"\x00\xd0\x20\x20" * 2  # two rows of one RGB texel each, filter 0
        chunk = lambda t, d: (struct.pack(">I", len(d)) + t + d +
                              struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF))
        png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 1, 2, 8, 2, 0, 0, 0)) +
               chunk(b"IDAT", zlib.compress(red)) + chunk(b"IEND", b""))
        with open(os.path.join(work, "red_texture.png"), "wb") as f:
            f.write(png)
        added = tab.eval("svetlo.addFiles([{name: 'textured.gltf', bytes: Uint8Array.from(atob(%s), "
                         "c => c.charCodeAt(0))}, {name: 'red_texture.png', bytes: "
                         "Uint8Array.from(atob(%s), c => c.charCodeAt(0))}])"
                         ".then(n => n, e => ({error: e.message}))"
                         % (json.dumps(base64.b64encode(json.dumps(textured).encode()).decode()),
                            json.dumps(base64.b64encode(png).decode())))
        r = tab.eval(RENDER % (json.dumps("textured.gltf"), json.dumps(opts)))
        native_file = os.path.join(work, "textured.pfm")
        subprocess.run([svetlo, "render", textured_file, "-e", "raster", "-W", "64", "-H", "48",
                        "--spp", "4", "--seed", "3", "-q", "-o", native_file], check=True)
        w, h, native = read_pfm(native_file)
        ok = bool(r) and "b64" in r and (r["width"], r["height"]) == (w, h)
        diff = relative_difference(floats(r), native) if ok else None
        check("a visitor's glTF with its texture beside it: the native program's image "
              "(relative RMS difference %s)" % ("%.2e" % diff if ok else "-"),
              added == ["textured.gltf", "red_texture.png"] and ok and diff <= 1e-6,
              (added, r and r.get("error")))

        # The same page from a server without the headers: one thread, the same pixels.
        plain = subprocess.Popen([sys.executable, os.path.join(HERE, "static_server.py"), web,
                                  "0"], stdout=subprocess.PIPE, text=True)
        plain_origin = origin
        try:
            plain_port = int(re.search(r"serving on (\d+)", plain.stdout.readline()).group(1))
            plain_origin = "http://127.0.0.1:%d/" % plain_port
            def open_page(query):
                tab.call("Page.navigate", url=plain_origin + "index.html?" + query)
                ready, end = None, time.time() + 120
                while time.time() < end and ready is None:
                    time.sleep(0.1)
                    ready = tab.eval("typeof svetlo !== 'undefined' && "
                                     "location.search.includes(%s) ? "
                                     "svetlo.ready.then(() => true, e => e.message) : null"
                                     % json.dumps(query.split("&")[0]))
                return ready

            # A link to a scene that is not there: its one-line error in the page, no image.
            open_page("scene=nonesuch.json&engine=raster")
            error, end = "", time.time() + 60
            while time.time() < end and not error:
                time.sleep(0.1)
                error = tab.eval("document.getElementById('error').textContent") or ""
            check("a link to a scene that is not there shows its one-line error",
                  error.startswith("nonesuch.json: scene:") and "\n" not in error, error)
            ready = open_page("scene=cornell.json&engine=whitted&set=render.shading=flat")
            check("without isolation: svetlo.ready settles", ready is True, ready)
            check("without isolation: the page is not isolated and says so",
                  tab.eval("self.crossOriginIsolated") is False and
                  "one thread" in (tab.eval("document.getElementById('threads').textContent") or ""))
            v = settle(tab)
            check("without isolation: the link's view renders on one thread",
                  bool(v) and v[1] > 100 and tab.eval("document.getElementById('engine').value")
                  == "whitted", v and v[1])
            change_ends_render(tab, "without isolation: ")
            # svetlo.cancel without shared memory: a new worker, the visitor's files given
            # again, and the next renders as before.
            tab.eval("svetlo.addFiles([{name: 'triangle.gltf', bytes: Uint8Array.from(atob(%s), "
                     "c => c.charCodeAt(0))}])" % json.dumps(b64))
            ended = tab.eval("""new Promise(resolve => { let first = null;
                svetlo.render('cornell.json', {engine: 'path', width: 64, height: 48,
                    spp: 1000000, onPass: () => { if (first === null) {
                        first = performance.now(); svetlo.cancel(); } }})
                .then(r => resolve({passes: r.passes, cancelled: r.cancelled,
                                    pixels: r.pixels.length, ms: performance.now() - first}),
                      e => resolve({error: e.message})); })""")
            check("without isolation: svetlo.cancel ends a render at once (%s)" % ended,
                  bool(ended) and ended.get("cancelled") is True and ended.get("passes") == 1
                  and ended.get("pixels") == 64 * 48 * 3 and ended.get("ms", 1e9) < 1000, ended)
            r = tab.eval(RENDER % (json.dumps("triangle.gltf"), json.dumps(opts_visitor)))
            check("without isolation: after svetlo.cancel the visitor's files are there",
                  bool(r) and "b64" in r and relative_difference(floats(r), visitor_native) <= 1e-6,
                  r and r.get("error"))
            for engine in ("raster", "path"):
                if engine not in isolated_pixels:
                    continue
                scene, opts, pixels = isolated_pixels[engine]
                r = tab.eval(RENDER % (json.dumps(scene), json.dumps(opts)))
                check("without isolation: %s gives the isolated page's pixels" % engine,
                      r and r.get("b64") == pixels, r and r.get("error"))
        finally:
            plain.kill()
        origin_ok = (origin, plain_origin)
        outside = [u for u in tab.requests if not (u.startswith(origin_ok) or u.startswith("data:")
                                                    or u.startswith("blob:"))]
        check("no request outside the page's origin", not outside, outside)
        check("no error in the console", not tab.errors, tab.errors)
    finally:
        browser.kill()
        server.kill()
        shutil.rmtree(profile, ignore_errors=True)
        shutil.rmtree(work, ignore_errors=True)
    print("%d failed" % len(failures) if failures else "all web checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
