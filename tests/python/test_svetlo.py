"""The Python module against the command line (docs/python.md): the same images bit for bit
for every engine, dict and file scenes alike, set as --set, diff and trace with the command
line's numbers; the GIL released and Ctrl-C honoured; every kind of bad input raising the
right exception and never crashing the interpreter."""
import json
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import svetlo
from conftest import ROOT, read_pfm

SMALL = dict(width=40, height=32)


def cli_render(svetlo_bin, tmp_path, scene, *args):
    out = str(tmp_path / "cli.pfm")
    subprocess.run([svetlo_bin, "render", scene, "-q", "-o", out] + list(args), check=True)
    return read_pfm(out)


@pytest.mark.parametrize("engine,scene", [("raster", "shadows.json"), ("whitted", "spheres.json"),
                                          ("path", "cornell.json"), ("radiosity", "cornell_radiosity.json")])
@pytest.mark.parametrize("threads", [1, 2])
def test_image_is_the_cli_pfm_bit_for_bit(svetlo_bin, scenes, tmp_path, engine, scene, threads):
    path = os.path.join(scenes, scene)
    r = svetlo.render(svetlo.load(path), engine=engine, spp=2, threads=threads, seed=3, **SMALL)
    cli = cli_render(svetlo_bin, tmp_path, path, "-e", engine, "--spp", "2", "-t", str(threads),
                     "--seed", "3", "-W", "40", "-H", "32")
    assert r.image.dtype == np.float32 and r.image.shape == (32, 40, 3)
    assert np.array_equal(r.image, cli)
    assert r.stats["spp"] == 2 and r.stats["engine"] == engine and r.stats["seconds"] > 0
    assert r.provenance["engine"] == engine and r.provenance["full_resolution"] == [40, 32]


def test_aovs_are_the_cli_aovs(svetlo_bin, scenes, tmp_path):
    path = os.path.join(scenes, "spheres.json")
    r = svetlo.render(path, engine="whitted", spp=1, aovs=["depth", "normal", "bvh_cost"], **SMALL)
    out = tmp_path / "depth.pfm"
    cost = tmp_path / "cost.pfm"
    subprocess.run([svetlo_bin, "render", path, "-q", "-e", "whitted", "--spp", "1", "-W", "40",
                    "-H", "32", "-o", str(tmp_path / "x.pfm"), "--aov", "depth=%s" % out,
                    "--aov", "bvh_cost=%s" % cost], check=True)
    assert np.array_equal(r.aovs["depth"], read_pfm(str(out)))
    assert np.array_equal(r.aovs["bvh_cost"], read_pfm(str(cost)))
    assert sorted(r.aovs) == ["bvh_cost", "depth", "normal"]


def test_results_share_no_memory(scenes):
    r1 = svetlo.render(os.path.join(scenes, "cornell.json"), engine="raster", **SMALL)
    r2 = svetlo.render(os.path.join(scenes, "cornell.json"), engine="raster", **SMALL)
    assert r1.image.flags.owndata and r1.image.flags.writeable
    r1.image[:] = 0  # the renderer keeps nothing that the next render would show
    assert r2.image.any() and not np.shares_memory(r1.image, r2.image)


def test_dict_and_file_scenes_give_one_image(scenes):
    path = os.path.join(scenes, "shadows.json")
    with open(path) as f:
        as_dict = json.load(f)
    a = svetlo.render(svetlo.load(path), **SMALL)
    b = svetlo.render(svetlo.Scene(as_dict, base=scenes), **SMALL)
    assert np.array_equal(a.image, b.image)


def test_set_is_cli_set(svetlo_bin, scenes, tmp_path):
    path = os.path.join(scenes, "shadows.json")
    scene = svetlo.load(path)
    scene["lights.0.intensity"] = [5, 5, 5]
    scene.set("render.shadows", "map")
    assert scene["lights.0.intensity"] == [5, 5, 5] and scene.to_dict()["render"]["shadows"] == "map"
    cli = cli_render(svetlo_bin, tmp_path, path, "--set", "lights.0.intensity=[5,5,5]",
                     "--set", 'render.shadows="map"', "-W", "40", "-H", "32")
    assert np.array_equal(svetlo.render(scene, **SMALL).image, cli)
    # render's own set= is the same rule
    again = svetlo.render(path, set={"lights.0.intensity": [5, 5, 5], "render.shadows": "map"}, **SMALL)
    assert np.array_equal(again.image, cli)


def test_diff_is_cli_diff(svetlo_bin, scenes, tmp_path):
    path = os.path.join(scenes, "cornell.json")
    a, b = tmp_path / "a.pfm", tmp_path / "b.pfm"
    subprocess.run([svetlo_bin, "render", path, "-q", "-e", "raster", "-W", "40", "-H", "32", "-o", str(a)], check=True)
    subprocess.run([svetlo_bin, "render", path, "-q", "-e", "path", "--spp", "2", "-W", "40", "-H", "32", "-o", str(b)], check=True)
    out = subprocess.run([svetlo_bin, "diff", str(a), str(b)], capture_output=True, text=True).stdout
    cli = {line.split()[0]: float(line.split()[1]) for line in out.splitlines()}
    ours = svetlo.diff(read_pfm(str(a)), read_pfm(str(b)))
    for metric in ("mae", "rmse", "relmse", "flip"):
        assert ours[metric] == pytest.approx(cli[metric], rel=1e-5), metric
    assert svetlo.diff(str(a), str(b), metric="flip") == pytest.approx(cli["flip"], rel=1e-5)
    with pytest.raises(ValueError):
        svetlo.diff(read_pfm(str(a)), read_pfm(str(b)), metric="psnr")


def test_trace_is_cli_trace(svetlo_bin, scenes, tmp_path):
    path = os.path.join(scenes, "cornell.json")
    out = tmp_path / "t.json"
    subprocess.run([svetlo_bin, "trace", path, "-e", "path", "--pixel", "20,12", "--sample", "3",
                    "-W", "40", "-H", "32", "--json", str(out)], check=True, capture_output=True)
    ours = svetlo.trace(path, (20, 12), sample=3, engine="path", **SMALL)
    assert ours == json.load(open(out))


def test_progress_is_called_after_each_pass(scenes):
    calls = []
    svetlo.render(os.path.join(scenes, "cornell.json"), engine="path", spp=4,
                  progress=lambda f, spp, s: calls.append((f, spp, s)), **SMALL)
    assert [c[1] for c in calls] == [1, 2, 3, 4] and calls[-1][0] == 1.0
    one = []
    svetlo.render(os.path.join(scenes, "cornell.json"), engine="whitted",
                  progress=lambda f, spp, s: one.append(f), **SMALL)
    assert one == [1.0]


def test_the_gil_is_released(scenes):
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    before = len(ticks)
    svetlo.render(os.path.join(scenes, "cornell.json"), engine="path", spp=16, width=160,
                  height=160, threads=1)
    during = len(ticks) - before
    stop.set()
    t.join()
    assert during > 20, during


def test_ctrl_c_stops_the_render():
    script = """
import signal, sys, time, svetlo
t0 = time.time()
try:
    svetlo.render(%r, engine="path", spp=100000, width=64, height=64, threads=1)
    print("finished")
except KeyboardInterrupt:
    print("interrupted %%.1f" %% (time.time() - t0))
""" % os.path.join(ROOT, "scenes", "cornell.json")
    env = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(svetlo.__file__)))
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True,
                         env=env)
    time.sleep(2.0)
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=30)
    assert out.startswith("interrupted"), out


def test_repr_png(scenes):
    r = svetlo.render(os.path.join(scenes, "cornell.json"), engine="raster", **SMALL)
    assert r._repr_png_()[:8] == b"\x89PNG\r\n\x1a\n"


def test_triangles(scenes):
    positions, indices = svetlo.load(os.path.join(scenes, "cornell.json")).triangles()
    assert positions.dtype == np.float32 and positions.shape[1] == 3
    assert indices.dtype == np.uint32 and indices.shape[1] == 3 and indices.max() < len(positions)


def test_bad_keywords_and_types_raise_type_error(scenes):
    path = os.path.join(scenes, "cornell.json")
    with pytest.raises(TypeError, match="spq"):
        svetlo.render(path, spq=4)
    with pytest.raises(TypeError, match="spp"):
        svetlo.render(path, spp="4")
    with pytest.raises(TypeError, match="threads"):
        svetlo.render(path, threads=1.5)
    with pytest.raises(TypeError, match="aovs"):
        svetlo.render(path, aovs="depth")
    with pytest.raises(TypeError):
        svetlo.Scene([1, 2])
    with pytest.raises(TypeError):
        svetlo.render(42)


def test_scene_errors_raise_scene_error(scenes):
    path = os.path.join(scenes, "cornell.json")
    assert issubclass(svetlo.SceneError, ValueError)
    # A keyword that stands for a scene key is checked in that key's range and named as the
    # call names it, by the rule the command line's flags follow (which name -W, --spp).
    with pytest.raises(svetlo.SceneError, match=r": spp: must be "):
        svetlo.render(path, spp=0)
    with pytest.raises(svetlo.SceneError, match=r": width: must be "):
        svetlo.render(path, width=-3)
    with pytest.raises(svetlo.SceneError, match=r": seed: must be "):
        svetlo.trace(path, (0, 0), seed=-1)
    with pytest.raises(svetlo.SceneError, match=r": height: must be "):
        svetlo.compare(path, ["raster"], height=100000)
    # set= is read as --set is, and named by its key.
    with pytest.raises(svetlo.SceneError, match="render.spp"):
        svetlo.render(path, set={"render.spp": 0})
    with pytest.raises(svetlo.SceneError, match="render.engine"):
        svetlo.render(path, engine="phong")
    with pytest.raises(svetlo.SceneError, match="unknown AOV"):
        svetlo.render(path, aovs=["depths"])
    with pytest.raises(svetlo.SceneError, match="planar"):
        svetlo.render(path, engine="raster", aovs=["planar"])
    # The time budget's rule is the command line's (--time): its range and the engine.
    with pytest.raises(svetlo.SceneError, match=r"time: needs a progressive engine \(path\); raster"):
        svetlo.render(path, engine="raster", time=1)
    for bad in (0, -1, 1e9, float("nan"), float("inf")):
        with pytest.raises(svetlo.SceneError, match=r"time: must be a number of seconds in \(0, 604800\]"):
            svetlo.render(path, engine="path", time=bad)
    scene = svetlo.load(path)
    with pytest.raises(svetlo.SceneError, match="camera.fov"):
        scene["camera.fov"] = 200
    assert scene["camera.fov"] != 200  # a refused change leaves the scene as it was
    with pytest.raises(svetlo.SceneError, match="nan"):
        scene["camera.fov"] = float("nan")
    with pytest.raises(svetlo.SceneError, match="inf"):
        svetlo.Scene({"camera": {"fov": float("inf")}})
    with pytest.raises(svetlo.SceneError):
        svetlo.load(os.path.join(scenes, "no_such_scene.json"))
    with pytest.raises(svetlo.SceneError, match="--pixel"):
        svetlo.trace(path, (4000, 0))
    # the message is the command line's line after "svetlo: error: ", with the keyword's name
    # where the command line names its flag
    with pytest.raises(svetlo.SceneError) as e:
        svetlo.render(path, spp=0)
    assert str(e.value) == path + ": spp: must be >= 1 (is 0)"


def test_fuzz_corpus_as_the_command_line_reads_it(svetlo_bin, tmp_path):
    """Each scene of the fuzz corpus, given to Python as a dict, does what the command line does
    with its file: the same pixels where it renders, the same one-line error (but for the
    file's name) where it is refused."""
    corpus = os.path.join(ROOT, "tests", "fuzz", "corpus", "scene")
    compared = 0
    for name in sorted(os.listdir(corpus)):
        path = os.path.join(corpus, name)
        try:
            with open(path) as f:
                as_dict = json.load(f)
        except ValueError:
            continue  # not JSON: the file parser's (fuzz_replay_test's)
        if not isinstance(as_dict, dict):
            continue
        out = str(tmp_path / (name + ".pfm"))
        cli = subprocess.run([svetlo_bin, "render", path, "-W", "16", "-H", "12", "--spp", "1",
                              "-t", "1", "-q", "-o", out], capture_output=True, text=True)
        if cli.returncode == 0:
            r = svetlo.render(svetlo.Scene(as_dict, base=corpus), width=16, height=12, spp=1,
                              threads=1)
            assert np.array_equal(r.image, read_pfm(out)), name
        else:
            line = cli.stderr.strip().splitlines()[-1]
            assert line.startswith("svetlo: error: " + path + ": "), line
            with pytest.raises(svetlo.SceneError) as refused:
                svetlo.render(svetlo.Scene(as_dict, base=corpus), width=16, height=12, spp=1,
                              threads=1)
            # The same key and message; the file is named as each caller names it.
            assert str(refused.value).split(": ", 1)[1] == line.split(path + ": ", 1)[1], name
        compared += 1
    assert compared >= 4  # the corpus's scenes that are JSON objects


def test_compare_is_cli_compare(svetlo_bin, scenes, tmp_path):
    path = os.path.join(scenes, "cornell.json")
    specs = ["raster:render.shading=gouraud", "whitted", "path:render.spp=2"]
    args = []
    for spec in specs:
        args += ["-T", spec]
    out = tmp_path / "m.json"
    subprocess.run([svetlo_bin, "compare", path, *args, "--reference", "path:render.spp=4",
                    "-W", "40", "-H", "32", "--json", str(out), "-q"], check=True)
    cli = json.load(open(out))
    ours = svetlo.compare(path, specs, reference="path:render.spp=4", html=tmp_path / "s.html",
                          **SMALL)
    assert list(ours) == ["scene", "reference", "techniques"]
    assert [t["spec"] for t in ours["techniques"]] == specs
    for a, b in zip(ours["techniques"], cli["techniques"]):
        for metric in ("mae", "rmse", "relmse", "flip"):
            assert a[metric] == b[metric], (a["spec"], metric)
    assert (tmp_path / "s.html").read_text().startswith("<!DOCTYPE html>")
    with pytest.raises(svetlo.SceneError, match="-T phong"):
        svetlo.compare(path, ["phong"], **SMALL)


def test_a_model_alone_loads_and_renders_as_the_cli_renders_it(svetlo_bin, tmp_path):
    # docs/scene-format.md, "A model alone": the same scene, framed and lit, bit for bit.
    model = os.path.join(ROOT, "tests", "data", "tetra_part.obj")
    scene = svetlo.load(model)
    assert scene["camera"]["fov"] == 40 and scene["lights"][0]["type"] == "directional"
    r = svetlo.render(scene, engine="raster", width=32, height=24, seed=0, threads=2)
    out = tmp_path / "model.pfm"
    subprocess.run([svetlo_bin, "render", model, "-e", "raster", "-W", "32", "-H", "24",
                    "--seed", "0", "-t", "2", "-q", "-o", str(out)], check=True)
    assert r.image.max() > 0.05
    assert np.array_equal(r.image, read_pfm(out))


def test_every_caller_makes_the_same_job(svetlo_bin, scenes, tmp_path):
    """The command line's flags, Python's keywords and the viewer's query, asking for the same
    render, make one job (src/svetlo/job/): the same effective scene in their images'
    provenance, and the viewer's image the command line's pixel for pixel."""
    import socket
    import urllib.request
    path = os.path.join(scenes, "cornell.json")
    cli_png = str(tmp_path / "cli.png")
    subprocess.run([svetlo_bin, "render", path, "-q", "-o", cli_png, "-e", "raster", "-W", "40",
                    "-H", "32", "--spp", "2", "--set", "render.shading=phong", "--set",
                    "camera.fov=35"], check=True)

    def provenance(image):
        out = subprocess.run([svetlo_bin, "info", image, "--json"], capture_output=True,
                             text=True, check=True).stdout
        return json.loads(out)

    cli = provenance(cli_png)
    py = svetlo.render(path, engine="raster", width=40, height=32, spp=2,
                       set={"render.shading": "phong", "camera.fov": 35}).provenance
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    server = subprocess.Popen([svetlo_bin, "serve", scenes, "--port", str(port)],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        base = "http://127.0.0.1:%d" % port
        for _ in range(100):
            try:
                urllib.request.urlopen(base + "/api/status", timeout=1).read()
                break
            except OSError:
                time.sleep(0.1)
        query = ("/api/render?scene=cornell.json&engine=raster&width=40&height=32&spp=2"
                 "&set=render.shading=phong&set=camera.fov%3D35")
        view_png = str(tmp_path / "view.png")
        with open(view_png, "wb") as f:
            f.write(urllib.request.urlopen(base + query, timeout=60).read())
    finally:
        server.terminate()
        server.wait()
    view = provenance(view_png)
    assert cli["scene"] == py["scene"] == view["scene"]
    assert cli["scene"]["render"]["shading"] == "phong" and cli["scene"]["camera"]["fov"] == 35
    assert np.array_equal(svetlo.read_image(cli_png), svetlo.read_image(view_png))
