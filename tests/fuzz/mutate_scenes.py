"""Scene mutation: the bundled scenes, mutated, rendered by every engine, against docs/robustness.md's rule.

    /usr/bin/python3 tests/fuzz/mutate_scenes.py SVETLO [--runs N] [--seed S] [--timeout T]
        [--found DIR]

The libFuzzer targets (make fuzz) check the loaders; this checks the whole program on scenes
that still parse. Each run takes a scene of scenes/, changes one to eight of its values
(most often numbers: set to 0, -1, 1e-30, 1e38, 2^31, ...; else an array shortened,
lengthened or emptied, a key deleted, a value replaced by another type or by another value
of the scene), and renders it with a random engine, film size, spp, thread count, output
format, seed, AOV and time budget. The command line (docs/robustness.md) allows two outcomes:

- exit 0, the image written, nothing on stderr (--quiet), and in a PFM output every value
  finite and non-negative;
- exit 1, one line `svetlo: error: FILE: ...` naming the scene, a file it reads or an output
  of the command line, and no output (image or AOV) written.

Anything else (a signal, a sanitizer's report, another exit status, more lines, a partial
output, a run longer than --timeout) is kept in --found with the command that made it.
Meant for the sanitizer build (make fuzz-scenes). Python's standard library only."""
import argparse
import copy
import json
import math
import os
import random
import shutil
import struct
import subprocess
import sys
import tempfile
import time

# Numbers that break careless code: zeros, signs, denormal-ish and huge magnitudes, integer
# limits, and plain small counts.
NUMBERS = [0, -1, -0.0, 1e-30, 1e-7, -1e-7, 0.5, 1, 2, 7, 65536, 100000, 1e9, 2147483648,
           -2147483649, 4294967296, 1e30, 3.4e38, 1e300]
# Values of another type.
STRANGERS = [None, True, "x", "", {}, [], 0, [0, 0, 0], [1e38, 1e38, 1e38],
             {"checker": {"a": 1, "b": 0, "scale": 0}}]
# The radiosity engine meshes every curved surface into patches: these scenes take minutes
# there even unmutated (docs/radiosity.md, "Known weaknesses"), so they go to the others.
SLOW_FOR_RADIOSITY = {"materials.json", "mis.json", "raster.json", "shadows.json",
                      "spheres.json"}


def nodes(value, path=()):
    """Every (path, value) below the root."""
    if isinstance(value, dict):
        for k, v in value.items():
            yield path + (k,), v
            yield from nodes(v, path + (k,))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield path + (i,), v
            yield from nodes(v, path + (i,))


def is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def parent(root, path):
    for k in path[:-1]:
        root = root[k]
    return root


def mutate(scene, rng):
    scene = copy.deepcopy(scene)
    for _ in range(rng.choice([1, 1, 2, 3, 5, 8])):
        candidates = list(nodes(scene))
        numbers = [c for c in candidates if is_number(c[1])]
        if not candidates:
            break
        # Mostly numbers: a scene with a key gone or of the wrong type is refused at once, so
        # those mutations say less about the engines.
        path, value = rng.choice(numbers if numbers and rng.random() < 0.6 else candidates)
        holder, key = parent(scene, path), path[-1]
        r = rng.random()
        if is_number(value) and r < 0.8:
            holder[key] = (rng.choice(NUMBERS) if rng.random() < 0.7
                           else value * rng.choice([-1, 10, 1000, 1e-6]))
        elif isinstance(value, list) and r < 0.5:
            c = rng.random()
            if c < 0.3:
                holder[key] = value[:-1]
            elif c < 0.6:
                holder[key] = value + [value[-1] if value else 0]
            elif c < 0.8:
                holder[key] = []
            else:
                holder[key] = [rng.choice(NUMBERS)] * len(value)
        elif r < 0.7:
            del holder[key]
        elif r < 0.85:
            holder[key] = copy.deepcopy(rng.choice(STRANGERS))
        else:
            holder[key] = copy.deepcopy(rng.choice(candidates)[1])
    return scene


def pfm_problem(path, signed):
    """None if the PFM's every value is finite (and non-negative unless `signed`), else what
    is wrong."""
    with open(path, "rb") as f:
        kind = f.readline().strip()
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        data = f.read()
    channels = 3 if kind == b"PF" else 1
    count = width * height * channels
    if len(data) != 4 * count:
        return f"{len(data)} bytes of data for {count} values"
    values = struct.unpack(("<" if scale < 0 else ">") + f"{count}f", data)
    bad = [v for v in values if not (math.isfinite(v) and (signed or v >= 0.0))]
    return f"{len(bad)} values out of range, e.g. {bad[0]}" if bad else None


def workspace(repo):
    """A folder laid out as the repository around scenes/, so that the mutated scenes' own
    relative paths (../tests/data, textures/, ../../shared/data) resolve."""
    root = tempfile.mkdtemp(prefix="svetlo_mutants_")
    os.makedirs(os.path.join(root, "repo", "scenes"))
    links = {("repo", "tests"): os.path.join(repo, "tests"),
             ("repo", "scenes", "textures"): os.path.join(repo, "scenes", "textures"),
             ("shared",): os.path.join(repo, "..", "shared")}
    for where, target in links.items():
        if os.path.exists(target):
            os.symlink(os.path.realpath(target), os.path.join(root, *where))
    return root, os.path.join(root, "repo", "scenes")


def random_command(rng, svetlo, scene_path, engine, root, run):
    """The render command for a mutant, its image's path, and its AOV's (path, name) or
    (None, None)."""
    width, height = rng.choice([(24, 16), (1, 1), (3, 200), (17, 5)])
    out = os.path.join(root, f"out_{run}" + rng.choice([".png", ".pfm", ".exr"]))
    cmd = [svetlo, "render", scene_path, "-o", out, "--engine", engine, "-W", str(width),
           "-H", str(height), "--spp", rng.choice("123"), "-t", rng.choice("12"), "--quiet"]
    aov, name_aov = None, None
    if rng.random() < 0.3:
        aov = os.path.join(root, f"aov_{run}.pfm")
        name_aov = rng.choice(["depth", "normal", "albedo", "visibility", "patches"])
        cmd += ["--aov", f"{name_aov}={aov}"]
    if engine == "path" and rng.random() < 0.2:
        cmd += ["--time", rng.choice(["0.01", "0.5"])]
    if rng.random() < 0.2:
        cmd += ["--seed", rng.choice(["0", "4294967295", "123456789012"])]
    return cmd, out, (aov, name_aov)


def contract_problem(status, stderr, scene_path, out, aov, name_aov):
    """None if a run ended in one of docs/robustness.md's two outcomes, else what broke it."""
    lines = [l for l in stderr.splitlines() if l.strip()]
    written = [f for f in (out, aov) if f and os.path.exists(f)]
    if status == 0:
        if lines or out not in written:
            return "exit 0 with stderr, or without the image"
        pfms = [f for f in written if f.endswith(".pfm")]
        problems = [pfm_problem(f, f == aov and name_aov == "normal") for f in pfms]
        return next((p for p in problems if p), None)
    if status == 1:
        prefix = "svetlo: error: "
        named = lines[0].removeprefix(prefix).split(": ")[0] if lines else ""
        if (len(lines) != 1 or not lines[0].startswith(prefix) or
                not (named in (scene_path, out, aov) or os.path.exists(named))):
            return "exit 1 without one error line naming a file"
        return "exit 1 with output written" if written else None
    return f"exit status {status}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("svetlo")
    ap.add_argument("--runs", type=int, default=500)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=60.0, help="seconds a run may take")
    ap.add_argument("--found", default="build-asan/mutants", help="where failures are kept")
    args = ap.parse_args()
    repo = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    scenes = {f: json.load(open(os.path.join(repo, "scenes", f)))
              for f in sorted(os.listdir(os.path.join(repo, "scenes"))) if f.endswith(".json")}
    names = sorted(scenes)
    rng = random.Random(args.seed)
    root, here = workspace(repo)
    failures = rendered = 0
    started = time.time()
    try:
        for run in range(args.runs):
            name = rng.choice(names)
            engines = ["raster", "whitted", "path"]
            if name not in SLOW_FOR_RADIOSITY:
                engines.append("radiosity")
            engine = rng.choice(engines)
            scene_path = os.path.join(here, f"mutant_{run}.json")
            with open(scene_path, "w") as f:
                json.dump(mutate(scenes[name], rng), f)
            cmd, out, (aov, name_aov) = random_command(rng, args.svetlo, scene_path, engine,
                                                       root, run)
            t0 = time.time()
            try:
                p = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout)
                status, stderr = p.returncode, p.stderr
            except subprocess.TimeoutExpired:
                status, stderr = f"none: past {args.timeout} s", ""
            problem = contract_problem(status, stderr, scene_path, out, aov, name_aov)
            if problem:
                failures += 1
                os.makedirs(args.found, exist_ok=True)
                kept = os.path.join(args.found, f"seed{args.seed}_run{run}_{name}")
                shutil.copy(scene_path, kept)
                print(f"FAIL run {run} ({name}, {engine}, {time.time() - t0:.1f} s): {problem}\n"
                      f"  {' '.join(cmd)}\n  scene kept as {kept}\n  " +
                      "\n  ".join(stderr.splitlines()[:8]), flush=True)
            elif status == 0:
                rendered += 1
            for f in (scene_path, out, aov):
                if f and os.path.exists(f):
                    os.remove(f)
    finally:
        shutil.rmtree(root, ignore_errors=True)
    print(f"{args.runs} mutated scenes in {time.time() - started:.0f} s: {rendered} rendered, "
          f"{args.runs - rendered - failures} refused, {failures} broke the rule")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
