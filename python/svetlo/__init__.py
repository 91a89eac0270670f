"""svetlo from Python: scenes as dicts, renders as numpy arrays (docs/python.md).

    import svetlo
    scene = svetlo.load("scenes/cornell.json")          # or svetlo.Scene(dict)
    scene["render.max_depth"] = 4                        # the dotted keys of --set
    r = svetlo.render(scene, engine="path", spp=64, width=256, height=256, aovs=["depth"])
    r.image                                              # H x W x 3 float32, linear RGB
    svetlo.diff(r.image, reference, metric="relmse")     # the numbers of `svetlo diff`

Bad input raises SceneError (a ValueError) with the command line's one-line message
(FILE: WHERE: WHAT); a wrong keyword or type raises TypeError, naming it.
"""

import json
import math
import os

from . import _svetlo

SceneError = _svetlo.SceneError

__all__ = ["Scene", "Result", "SceneError", "load", "render", "trace", "diff", "compare",
           "read_image"]


def _check_finite(value, where, name):
    """Raises SceneError for a NaN or infinity anywhere in value (JSON has neither)."""
    if isinstance(value, float) and not math.isfinite(value):
        raise SceneError("%s: %s: must be a finite number (is %r)" % (name, where or "scene", value))
    if isinstance(value, dict):
        for k, v in value.items():
            _check_finite(v, "%s.%s" % (where, k) if where else str(k), name)
    elif isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            _check_finite(v, "%s.%d" % (where, i) if where else str(i), name)


def _json(value, where, name):
    """value as JSON text, after the checks the scene file's parser makes."""
    _check_finite(value, where, name)
    try:
        return json.dumps(value, allow_nan=False)
    except TypeError as e:
        raise TypeError("%s: %s" % (where or "scene", e)) from None


class Scene:
    """A scene: its effective JSON, checked as a scene file is on every change.

    Scene(dict) builds one from a dict in the scene format (docs/scene-format.md); relative
    file names in it are read from `base` (default: the current folder). svetlo.load(path)
    reads a file. scene[key] and scene.set(key, value) take the dotted keys of --set
    ("lights.0.intensity"); scene.to_dict() gives the JSON back.
    """

    def __init__(self, scene, base=None, _path=None, _sha256=None):
        if isinstance(scene, Scene):
            scene = scene.to_dict()
        if not isinstance(scene, dict):
            raise TypeError("Scene() takes a dict, not %s" % type(scene).__name__)
        self._path = _path or os.path.join(os.path.abspath(base or os.getcwd()), "<dict>")
        self._text = _json(scene, "", self._path)
        _svetlo.validate(self._text, self._path)
        self._sha256 = _sha256 or _svetlo.sha256_text(self._text)

    @property
    def path(self):
        """The file the scene came from (a dict's: BASE/<dict>), as messages name it."""
        return self._path

    def to_dict(self):
        """The scene's JSON as a new dict (every override applied)."""
        return json.loads(self._text)

    def set(self, key, value):
        """Sets a dotted key (as --set KEY=VALUE), checked as the file is: SceneError if not."""
        if not isinstance(key, str):
            raise TypeError("a scene key is a str, not %s" % type(key).__name__)
        self._text = _svetlo.set_key(self._text, self._path, key, _json(value, key, self._path))
        self._sha256 = _svetlo.sha256_text(self._text)
        return self

    def __setitem__(self, key, value):
        self.set(key, value)

    def __getitem__(self, key):
        if not isinstance(key, str):
            raise TypeError("a scene key is a str, not %s" % type(key).__name__)
        node = self.to_dict()
        for part in key.split("."):
            if isinstance(node, list) and part.isdigit() and int(part) < len(node):
                node = node[int(part)]
            elif isinstance(node, dict) and part in node:
                node = node[part]
            else:
                raise KeyError(key)
        return node

    def triangles(self):
        """(positions, indices): the scene's triangles as the rasterizer tessellates them,
        world space, N x 3 float32 and M x 3 uint32 (counter-clockwise from the front)."""
        return _svetlo.triangles(self._text, self._path)

    def __repr__(self):
        return "svetlo.Scene(%r)" % self._path


def load(path):
    """Reads a scene file (JSON), checked as `svetlo render` checks it."""
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError("load() takes a path, not %s" % type(path).__name__)
    path = os.fspath(path)
    text = _svetlo.read_scene(path)
    return Scene(json.loads(text), _path=path, _sha256=_svetlo.sha256_file(path))


class Result:
    """A render: `image` (H x W x 3 float32, linear RGB, the command line's PFM bit for bit),
    `aovs` (name: H x W x 3 float32), `stats` (seconds, setup_seconds, spp, rays, nonfinite,
    engine) and `provenance` (the dict an image file carries). Shown as a PNG in Jupyter."""

    def __init__(self, raw):
        self.image = raw["image"]
        self.aovs = raw["aovs"]
        self.stats = raw["stats"]
        self.provenance = json.loads(raw["provenance"])
        self._exposure = raw["exposure"]

    def _repr_png_(self):
        return _svetlo.png(self.image, self._exposure)

    def __repr__(self):
        h, w, _ = self.image.shape
        return "<svetlo.Result %s %dx%d, %d spp, %.3f s>" % (
            self.stats["engine"], w, h, self.stats["spp"], self.stats["seconds"])


def _as_scene(scene):
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, dict):
        return Scene(scene)
    if isinstance(scene, (str, os.PathLike)):
        return load(scene)
    raise TypeError("expected a svetlo.Scene, a dict or a path, not %s" % type(scene).__name__)


def _require_int(name, value):
    """TypeError unless value is an int (bool is not one here)."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise TypeError("%s must be an int, not %s" % (name, type(value).__name__))


def _int(name, value, lo, hi, where):
    if value is None:
        return None
    _require_int(name, value)
    if not lo <= value <= hi:
        raise SceneError("<python>: %s: must be in [%d, %d] (is %d)" % (where, lo, hi, value))
    return value


def _request(scene, engine, width, height, spp, seed, set):
    """The call's keyword arguments as the job layer takes them (docs/python.md): `set` as
    (KEY, JSON value) overrides, and the keywords that stand for scene keys as text, which the
    module checks in their ranges and applies after `set` (they win), by the rule the command
    line's flags follow (job/overrides.h), naming each as it is named here."""
    overrides = []
    if set is not None:
        if not isinstance(set, dict):
            raise TypeError("set must be a dict of KEY: value, not %s" % type(set).__name__)
        for key, value in set.items():
            if not isinstance(key, str):
                raise TypeError("set's keys are str, not %s" % type(key).__name__)
            overrides.append((key, _json(value, key, scene.path)))
    keywords = {}
    if engine is not None:
        if not isinstance(engine, str):
            raise TypeError("engine must be a str, not %s" % type(engine).__name__)
        keywords["engine"] = engine
    for name, value in (("width", width), ("height", height), ("spp", spp), ("seed", seed)):
        if value is not None:
            _require_int(name, value)
            keywords[name] = str(value)
    return overrides, keywords


def _threads(threads):
    return _int("threads", threads, 0, _svetlo.max_threads, "threads") or 0


def render(scene, *, engine=None, spp=None, width=None, height=None, threads=None, seed=None,
           time=None, set=None, aovs=None, progress=None):
    """Renders `scene` (a Scene, a dict or a path) and returns a Result.

    engine, spp, width, height and seed override the scene's keys as the command line's flags
    do, after `set` (a dict of dotted keys). `time`: seconds for the path tracer's passes.
    `aovs`: names of AOVs and debug AOVs (docs/cli.md). `progress(fraction, spp, seconds)` is
    called after each pass. The GIL is released while rendering; Ctrl-C ends the pass in
    progress and raises KeyboardInterrupt.
    """
    scene = _as_scene(scene)
    overrides, keywords = _request(scene, engine, width, height, spp, seed, set)
    if aovs is None:
        aovs = []
    if isinstance(aovs, str) or not all(isinstance(a, str) for a in aovs):
        raise TypeError("aovs must be a list of names (str)")
    budget = None  # its range and the engine are checked as --time's (render_job.h)
    if time is not None:
        if isinstance(time, bool) or not isinstance(time, (int, float)):
            raise TypeError("time must be a number of seconds, not %s" % type(time).__name__)
        budget = float(time)
    if progress is not None and not callable(progress):
        raise TypeError("progress must be callable (fraction, spp, seconds)")
    command = (["python", "svetlo.render"] + ["%s=%s" % kv for kv in overrides] +
               ["%s=%s" % kv for kv in keywords.items()])
    raw = _svetlo.render(scene._text, scene._path, scene._sha256, overrides, keywords, list(aovs),
                         _threads(threads), budget, command, progress)
    return Result(raw)


def trace(scene, pixel, *, sample=0, spp=None, engine=None, width=None, height=None, seed=None,
          threads=None, set=None):
    """svetlo trace: the rays of sample `sample` of `pixel` (x, y), as the dict of
    `svetlo trace --json` (docs/trace.md)."""
    scene = _as_scene(scene)
    if (not isinstance(pixel, (tuple, list)) or len(pixel) != 2
            or not all(isinstance(v, int) and not isinstance(v, bool) for v in pixel)):
        raise TypeError("pixel must be (x, y), two ints")
    sample = _int("sample", sample, 0, _svetlo.max_spp - 1, "sample")
    spp_value = _int("spp", spp, 1, _svetlo.max_spp, "spp") or 1
    overrides, keywords = _request(scene, engine, width, height, None, seed, set)
    text = _svetlo.trace(scene._text, scene._path, scene._sha256, overrides, keywords, pixel[0], pixel[1],
                         sample, spp_value, _threads(threads))
    return json.loads(text)


def compare(scene, techniques, *, reference=None, width=None, height=None, threads=None,
            seed=None, set=None, curves=False, html=None, png=None):
    """svetlo compare: each technique (a SPEC, "raster:render.shading=gouraud") against the
    reference (a SPEC or an image file; default path:render.spp=1024). Returns the dict of
    `compare --json`; with `html` or `png`, writes the sheet there too (docs/compare.md)."""
    scene = _as_scene(scene)
    if isinstance(techniques, str) or not all(isinstance(t, str) for t in techniques):
        raise TypeError("techniques must be a list of SPECs (str)")
    if reference is not None and not isinstance(reference, (str, os.PathLike)):
        raise TypeError("reference must be a SPEC or an image file")
    overrides, keywords = _request(scene, None, width, height, None, seed, set)
    text = _svetlo.compare(scene._text, scene._path, scene._sha256, overrides, keywords,
                           list(techniques),
                           os.fspath(reference) if reference is not None else "",
                           _threads(threads), bool(curves), os.fspath(html) if html else "",
                           os.fspath(png) if png else "")
    return json.loads(text)


def read_image(path):
    """An image file (PNG, PFM, EXR) as an H x W x 3 float32 array of linear RGB."""
    return _svetlo.read_image(os.fspath(path))[0]


def diff(a, b, metric=None, *, threads=None):
    """The metrics of `svetlo diff a b` (b is the reference): a dict of mae, rmse, relmse and
    flip, or the one value of `metric`. a and b are arrays (linear RGB: HDR-ꟻLIP) or image
    files (two PNGs: LDR-ꟻLIP on their sRGB values, as the command line)."""
    ldr = True
    images = []
    for x in (a, b):
        if isinstance(x, (str, os.PathLike)):
            image, x_ldr = _svetlo.read_image(os.fspath(x))
            ldr = ldr and x_ldr
            images.append(image)
        else:
            ldr = False
            images.append(x)
    if metric is not None and metric not in ("mae", "rmse", "relmse", "flip"):
        raise ValueError("unknown metric %r (expected mae, rmse, relmse or flip)" % (metric,))
    values = _svetlo.diff(images[0], images[1], ldr, _threads(threads))
    return values if metric is None else values[metric]
