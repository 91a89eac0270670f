"""The hard scenes' race (docs/performance.md, "The hard scenes"): the Cycles harness of
../shared/anchors/cycles, run inside Blender, with what `scenes/lamp_shade.json` and
`scenes/glass_caustic.json` need added to what it translates:

    blender -b --factory-startup --python bench/cycles/cycles_hard.py -- \
        --anchor ../shared/anchors/cycles --scene scenes/lamp_shade.json \
        --ladder 16,64,256,1024 --pairs -W 160 -H 120 --threads 2 --out-dir $O/ladder_lamp

Every option after --anchor DIR is the harness's own (cycles_cornell.py). Added:
- `cook_torrance` materials as a Principled BSDF with GGX (not the multiple-scattering form):
  base colour, metallic, roughness (Blender squares it into alpha, as glTF and svetlo do) and
  specular 0.5 (F0 = 0.04, svetlo's dielectric F0). Its diffuse lobe is Disney's, not svetlo's
  Lambert times (1 - F): the same material up to a few per cent of the table's brightness.
- `dielectric` materials (without dispersion) as a sharp Glass BSDF of the same ior: exact
  Fresnel and total internal reflection, as svetlo's.
- `cylinder` objects (no transform) as a closed mesh of 256 segments, its side smooth-shaded.
- boxes wound outward (see box_tris below), so that an emissive box emits outward as svetlo's.
The rest (camera, film, sampling, no clamping or denoising, one-sided emission) is the
harness's, unchanged.
"""
import math
import os
import sys

import bpy
import numpy as np


def anchor_dir():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if "--anchor" not in argv or argv.index("--anchor") + 1 >= len(argv):
        raise SystemExit("cycles_hard.py: --anchor DIR (the Cycles harness's folder) is needed")
    k = argv.index("--anchor")
    folder = argv[k + 1]
    # The harness parses the rest of the command line as its own.
    sys.argv = sys.argv[:sys.argv.index("--") + 1] + argv[:k] + argv[k + 2:]
    return os.path.abspath(folder)


sys.path.insert(0, anchor_dir())
import cycles_cornell  # noqa: E402
import scenegeom  # noqa: E402

SEGMENTS = 256


def box_tris(lo, hi):
    """A box's twelve triangles wound counter-clockwise seen from outside. The harness's
    box_tris winds them the other way (its bottom face, lo with edges ez then ex, faces +y),
    which a Lambert box never shows but an emissive one does: Cycles' one-sided emission then
    lights the inside only, and `lamp_shade.json`'s bulb (an emissive box) lit nothing."""
    lo = np.asarray(lo, dtype=np.float64)
    ex, ey, ez = np.diag(np.asarray(hi, dtype=np.float64) - lo)
    faces = [(lo, ex, ez), (lo + ey, ez, ex), (lo, ey, ex), (lo + ez, ex, ey), (lo, ez, ey),
             (lo + ex, ey, ez)]
    return [t for f in faces for t in scenegeom.quad_tris(*f)]


scenegeom.box_tris = box_tris


def cylinder_mesh(base, axis, radius):
    """(vertices, triangles, smooth flags) of a closed cylinder: the side's vertices shared
    around (smooth), each cap's own (flat). Counter-clockwise seen from outside."""
    base, axis = np.asarray(base, np.float64), np.asarray(axis, np.float64)
    a = axis / np.linalg.norm(axis)
    t = np.cross(a, [1.0, 0.0, 0.0] if abs(a[0]) < 0.9 else [0.0, 1.0, 0.0])
    t /= np.linalg.norm(t)
    b = np.cross(a, t)
    ring = [radius * (math.cos(2 * math.pi * k / SEGMENTS) * t +
                      math.sin(2 * math.pi * k / SEGMENTS) * b) for k in range(SEGMENTS)]
    verts, tris, smooth = [], [], []
    for k in range(SEGMENTS):  # the side: bottom ring 2k, top ring 2k + 1
        verts += [base + ring[k], base + axis + ring[k]]
    for k in range(SEGMENTS):
        i, j = 2 * k, 2 * ((k + 1) % SEGMENTS)
        tris += [(i, j, j + 1), (i, j + 1, i + 1)]
        smooth += [True, True]
    for cap, centre, sign in ((0, base, -1), (1, base + axis, 1)):
        first = len(verts)
        verts.append(centre)
        verts += [centre + r for r in ring]
        for k in range(SEGMENTS):
            i, j = first + 1 + k, first + 1 + (k + 1) % SEGMENTS
            tris.append((first, i, j) if sign > 0 else (first, j, i))
            smooth.append(False)
    return np.array(verts), tris, smooth


def scene_parts(scene, base, dedup=True):
    """scenegeom.scene_geometry, with cook_torrance and dielectric materials (their part's
    albedo is then a dict naming the material) and cylinders (a part's triangles are then
    (vertices, triangles, smooth flags))."""
    mats = scene.get("materials", {})
    plain, extra = dict(scene), []
    plain["objects"] = []
    for k, o in enumerate(scene["objects"]):
        m = mats.get(o.get("material", ""), {})
        if m.get("type") in ("cook_torrance", "dielectric") or o["type"] == "cylinder":
            where = f"objects[{k}]"
            if "transform" in o:
                raise SystemExit(f"{where}: transforms are not supported")
            if m.get("type") in ("lambert", "emissive"):
                alb = scenegeom.colour3(m.get("albedo", 0.8 if m["type"] == "lambert" else 0.0),
                                        where)
                emi = (scenegeom.colour3(m.get("radiance", 1.0), where)
                       if m["type"] == "emissive" else (0.0, 0.0, 0.0))
            elif m.get("type") in ("cook_torrance", "dielectric"):
                if m.get("dispersion") or m.get("abbe"):
                    raise SystemExit(f"{where}: a dispersive dielectric is not supported")
                alb, emi = dict(m), (0.0, 0.0, 0.0)
            else:
                raise SystemExit(f"{where}: material type {m.get('type')} is not supported")
            if o["type"] == "cylinder":
                geo = cylinder_mesh(o["base"], o["axis"], o["radius"])
            elif o["type"] == "quad":
                geo = np.array(scenegeom.quad_tris(o["corner"], o["edge_u"], o["edge_v"]))
            elif o["type"] == "box":
                geo = np.array(scenegeom.box_tris(o["min"], o["max"]))
            else:
                raise SystemExit(f"{where}: object type {o['type']} is not supported")
            extra.append((f"{k}_{o['type']}", geo, alb, emi))
        else:
            plain["objects"].append(o)
    parts, dropped = scenegeom.scene_geometry(plain, base, dedup)
    return parts + extra, dropped


def make_material(name, albedo, emission, two_sided):
    if not isinstance(albedo, dict):
        return harness_material(name, albedo, emission, two_sided)
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    out.target = "CYCLES"
    if albedo["type"] == "cook_torrance":
        bsdf = nt.nodes.new("ShaderNodeBsdfPrincipled")
        bsdf.distribution = "GGX"
        base = scenegeom.colour3(albedo.get("base_color", 0.8), name)
        bsdf.inputs["Base Color"].default_value = (*base, 1.0)
        bsdf.inputs["Metallic"].default_value = float(albedo.get("metallic", 0.0))
        bsdf.inputs["Roughness"].default_value = float(albedo.get("roughness", 0.5))
        bsdf.inputs["Specular"].default_value = 0.5
        bsdf.inputs["Sheen"].default_value = 0.0
        bsdf.inputs["Clearcoat"].default_value = 0.0
        nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    else:
        bsdf = nt.nodes.new("ShaderNodeBsdfGlass")
        bsdf.distribution = "SHARP"
        bsdf.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        bsdf.inputs["IOR"].default_value = float(albedo.get("ior", 1.5))
        nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    return m


def add_part(sc, name, geo, material):
    me = bpy.data.meshes.new(name)
    if isinstance(geo, tuple):
        verts, tris, smooth = geo
        me.from_pydata(verts.tolist(), [], tris)
        me.update()
        for poly, s in zip(me.polygons, smooth):
            poly.use_smooth = s
    else:
        me.from_pydata(geo.reshape(-1, 3).tolist(), [],
                       [(3 * i, 3 * i + 1, 3 * i + 2) for i in range(len(geo))])
        me.update()
    me.materials.append(material)
    sc.collection.objects.link(bpy.data.objects.new(name, me))


harness_material = cycles_cornell.make_material
cycles_cornell.make_material = make_material

# The harness links each part's triangles as a flat mesh; a cylinder's part carries its own
# mesh (shared, smooth side vertices), linked here after the harness has built the rest.
_build = cycles_cornell.build


def build(desc, base, args):
    cylinders = []

    def parts_without_cylinders(scene, folder, dedup=True):
        parts, dropped = scene_parts(scene, folder, dedup)
        kept = []
        for part in parts:
            (cylinders if isinstance(part[1], tuple) else kept).append(part)
        return kept, dropped

    cycles_cornell.scene_geometry = parts_without_cylinders
    sc = _build(desc, base, args)
    for name, geo, alb, emi in cylinders:
        add_part(sc, name, geo, make_material(name, alb, emi, args.two_sided_light))
    return sc


cycles_cornell.build = build
cycles_cornell.main()
