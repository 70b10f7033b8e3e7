"""Headless test of the dualspectra Blender add-on, run inside Blender.

    blender -b --factory-startup --python-exit-code 1 --python tests/blender/test_addon.py -- [options]
    python tests/blender/test_addon.py [options]        # with the PyPI ``bpy`` module

The add-on must be installed where Blender finds it: as a legacy add-on
(``$BLENDER_USER_SCRIPTS/addons/dualspectra_blender`` with the ``dualspectra`` package
as its subpackage; default) or, with ``--extension ZIP``, installed here from the Blender 4.2+
extension archive (the bundled wheel is installed by Blender). Then the test builds two
meshes, a lumpy closed surface and a part of it cut by a plane moved by a rigid motion,
gives both objects different transforms (non-uniform object scale included, the world
shapes unchanged), runs the operator and checks the selected vertices against the cut.
Also: the option properties are the library's table (``dualspectra.options_schema()``);
a second part located on the same object reuses the prepared ``Localizer`` and selects what
a fresh preparation selects; the confidence in the operator's report is the library's; loose
vertices and degenerate faces are the library's to drop (reported as a warning, the selection
still covers every vertex); a non-manifold partial is the library's to split (reported as a
warning), a closed one the library's to refuse (its message reported). The search (issue 21):
with the partial active and the full shape among other selected meshes, the full shape ranks
first (report and custom properties), its region is the library's, the decoys are untouched,
prepared shapes are reused, and errors name the object.

Exit status 1 on any failure (``--python-exit-code 1`` for the Blender binary).
"""

import argparse
import contextlib
import ctypes
import os
import re
import sys
import tempfile
import time
import traceback
import warnings

import bpy
import numpy as np
from mathutils import Euler, Matrix, Vector

# ---------------------------------------------------------------------------------------------
# options and add-on installation


def parse_args():
    if "--" in sys.argv:
        argv = sys.argv[sys.argv.index("--") + 1:]
    elif sys.argv and sys.argv[0].endswith(".py"):  # python test_addon.py ... (bpy module)
        argv = sys.argv[1:]
    else:  # the blender binary without "--": its own options are not ours
        argv = []
    p = argparse.ArgumentParser(prog="test_addon.py")
    p.add_argument("--extension", help="install this extension .zip (Blender 4.2+) instead of using a legacy add-on")
    p.add_argument("--k", type=int, default=10, help="eigenvalues per spectrum for the localization runs")
    p.add_argument("--max-iterations", type=int, default=40, help="trust-region iterations per start")
    p.add_argument("--time-limit", type=float, default=600.0, help="seconds allowed per localization run")
    p.add_argument("--subdivisions", type=int, default=4, help="icosphere subdivisions of the test shape")
    p.add_argument("--min-iou", type=float, default=0.7, help="lower bound for the IoU of the selected region")
    p.add_argument("--only", default="", help="comma-separated test names to run (default: all)")
    return p.parse_args(argv)


ARGS = parse_args()


def install_addon():
    """Enable the add-on and return its package name (``dualspectra_blender`` or ``bl_ext.*``)."""
    import addon_utils

    if ARGS.extension:
        bpy.ops.extensions.package_install_files(filepath=ARGS.extension, repo="user_default", enable_on_install=True)
        name = "bl_ext.user_default.dualspectra_blender"
    else:
        name = "dualspectra_blender"
        errors = []
        addon_utils.enable(name, default_set=True, handle_error=lambda exc: errors.append(exc))
        if errors:
            raise RuntimeError(f"enabling {name} failed: {errors[0]!r}")
    if name not in sys.modules:
        raise RuntimeError(f"add-on module {name} not loaded")
    if not hasattr(bpy.ops, "dualspectra") or not hasattr(bpy.types, "DUALSPECTRA_OT_localize"):
        raise RuntimeError("operator dualspectra.localize not registered")
    return name


ADDON = install_addon()
mesh_data = sys.modules[ADDON + ".mesh_data"]
job_module = sys.modules[ADDON + ".job"]
library = sys.modules[ADDON + ".library"]
cache_module = sys.modules[ADDON + ".cache"]
schema_module = sys.modules[ADDON + ".schema"]
operators = sys.modules[ADDON + ".operators"]
dualspectra = library.load()
print(f"Blender {bpy.app.version_string}, Python {sys.version.split()[0]}, add-on {ADDON}, "
      f"dualspectra {getattr(dualspectra, '__version__', '?')} from {dualspectra.__file__}")

# ---------------------------------------------------------------------------------------------
# test shapes (world space) and objects


BUMPS = [((1.0, 0.3, 0.2), 0.55, 0.20), ((-0.4, 1.0, -0.3), 0.35, 0.12), ((-0.3, -0.6, 1.0), 0.25, 0.08)]


def lumpy_surface(subdivisions, bumps=BUMPS, stretch=(1.3, 1.0, 0.8)):
    """An asymmetric closed surface: an icosphere pushed out by Gaussian ``bumps`` (direction,
    height, width) of different size, then stretched into an ellipsoid. Returns world vertices
    ``(n, 3)`` and faces ``(m, 3)``."""
    import bmesh

    bm = bmesh.new()
    try:
        bmesh.ops.create_icosphere(bm, subdivisions=subdivisions, radius=1.0)
        v = np.array([tuple(x.co) for x in bm.verts], dtype=np.float64)
        bm.verts.index_update()
        f = np.array([[x.index for x in face.verts] for face in bm.faces], dtype=np.int64)
    finally:
        bm.free()
    u = v / np.linalg.norm(v, axis=1, keepdims=True)
    r = np.ones(len(u))
    for centre, height, width in bumps:
        c = np.array(centre) / np.linalg.norm(centre)
        r += height * np.exp(-np.sum((u - c) ** 2, axis=1) / width)
    return u * r[:, None] * np.array(stretch), f


def cut_by_plane(v, f, normal, offset):
    """The faces whose three vertices satisfy ``normal . p > offset``; returns the partial
    mesh (compacted) and the full-mesh mask of its vertices (the ground-truth region)."""
    side = v @ np.asarray(normal, dtype=np.float64) > offset
    faces = f[side[f].all(axis=1)]
    used = np.zeros(len(v), dtype=bool)
    used[faces.ravel()] = True
    new = np.full(len(v), -1)
    new[used] = np.arange(used.sum())
    return v[used], new[faces], used


def make_object(name, world_vertices, faces, matrix_world):
    """A mesh object whose world-space shape is ``world_vertices`` under ``matrix_world``."""
    m = np.array(matrix_world, dtype=np.float64)
    local = (world_vertices - m[:3, 3]) @ np.linalg.inv(m[:3, :3]).T
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(local.tolist(), [], np.asarray(faces).tolist())
    mesh.validate()
    ob = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(ob)
    ob.matrix_world = Matrix(m.tolist())
    return ob


def rigid(v, angles, shift):
    rot = np.array(Euler(angles).to_matrix(), dtype=np.float64)
    return v @ rot.T + np.asarray(shift, dtype=np.float64)


def affine(location, rotation, scale):
    return Matrix.LocRotScale(Vector(location), Euler(rotation), Vector(scale))


def select_only(*objects, active):
    bpy.context.view_layer.update()  # bpy 4.5 keeps stale (None) entries until the layer syncs
    for ob in bpy.context.view_layer.objects:
        if ob is not None:
            ob.select_set(False)
    for ob in objects:
        ob.select_set(True)
    bpy.context.view_layer.objects.active = active


def selected_vertices(mesh):
    sel = np.zeros(len(mesh.vertices), dtype=bool)
    mesh.vertices.foreach_get("select", sel)
    return sel


def iou(a, b):
    return float((a & b).sum()) / max(1, int((a | b).sum()))


def clear_scene():
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    for me in list(bpy.data.meshes):
        bpy.data.meshes.remove(me)
    bpy.context.view_layer.update()


FULL_V, FULL_F = lumpy_surface(ARGS.subdivisions)
CUT_NORMAL, CUT_OFFSET = (0.9, 0.35, 0.25), 0.35
PART_V, PART_F, TRUTH = cut_by_plane(FULL_V, FULL_F, CUT_NORMAL, CUT_OFFSET)
PART_V_MOVED = rigid(PART_V, (1.0, -0.5, 2.0), (-4.0, 1.0, 0.5))
FULL_MATRIX = affine((1.0, 2.0, 3.0), (0.3, 0.2, 0.1), (1.5, 1.5, 1.5))
PART_MATRIX = affine((-4.0, 0.0, 0.0), (0.2, 0.9, -0.4), (0.5, 2.0, 1.0))  # non-uniform object scale
print(f"test shapes: full {len(FULL_V)} vertices / {len(FULL_F)} faces, partial {len(PART_V)} / {len(PART_F)}, "
      f"ground truth {int(TRUTH.sum())} vertices ({TRUTH.mean():.0%})")


def scene_pair():
    clear_scene()
    full = make_object("Full", FULL_V, FULL_F, FULL_MATRIX)
    part = make_object("Partial", PART_V_MOVED, PART_F, PART_MATRIX)
    select_only(full, part, active=full)
    return full, part


# ---------------------------------------------------------------------------------------------
# tests: bpy-free logic against Blender's own data and maths


def test_world_positions_match_mathutils():
    rng = np.random.default_rng(1)
    m = affine(rng.normal(size=3), rng.normal(size=3), rng.uniform(0.2, 3.0, size=3))
    local = rng.normal(size=(50, 3))
    got = mesh_data.world_positions(local, np.array(m))
    want = np.array([tuple(m @ Vector(p)) for p in local])
    scale = np.abs(want).max()
    assert np.abs(got - want).max() <= 64 * np.finfo(np.float32).eps * scale, np.abs(got - want).max()


def test_operator_properties_are_the_library_options():
    """Every option of dualspectra.options_schema() is an operator and a panel-settings property
    with the library's label, doc, default and range (ints clamped to Blender's 32 bits), and
    the choices as enum items; nothing else besides the operator's own four."""
    table = dualspectra.options_schema()
    assert table, "empty options table"
    operator_rna = bpy.ops.dualspectra.localize.get_rna_type()
    for rna in (operator_rna, bpy.context.scene.dualspectra.bl_rna):
        props = rna.properties
        for spec in table:
            p = props[spec["name"]]
            assert (p.name, p.description) == (spec["label"], spec["doc"]), spec["name"]
            if spec["type"] == "choice":
                assert p.type == 'ENUM' and [i.identifier for i in p.enum_items] == spec["choices"]
                assert p.default == spec["default"]
            else:
                assert p.type == {"int": 'INT', "float": 'FLOAT'}[spec["type"]], (spec["name"], p.type)
                assert np.isclose(p.default, spec["default"], rtol=1e-6), (spec["name"], p.default)
                assert p.hard_min == max(spec["min"], -2**31) and p.hard_max == min(spec["max"], 2**31 - 1), spec["name"]
    own = {"rna_type", "partial_object", "time_limit", "use_modifiers", "background"}
    names = {p.identifier for p in operator_rna.properties}
    assert names == own | {spec["name"] for spec in table}, names
    # Values go to the library as it names them; single-precision floats as their decimal.
    op_like = type("Op", (), {spec["name"]: spec["default"] for spec in table})()
    op_like.alpha = np.float32(0.33).item()
    values = schema_module.option_values(op_like, table)
    assert values["alpha"] == 0.33 and values["mode"] == "dual"
    dualspectra.Localizer(FULL_V, FULL_F, **dict(values, resolution=0, plane_cuts=2))  # accepted as they are


def test_nearest_indices_match_brute_force():
    rng = np.random.default_rng(2)
    points = rng.normal(size=(300, 3))
    queries = rng.normal(size=(97, 3))
    got = mesh_data.nearest_indices(queries, points, chunk=10)
    want = np.array([np.argmin(((points - q) ** 2).sum(axis=1)) for q in queries])
    assert np.array_equal(got, want)
    assert np.array_equal(mesh_data.nearest_indices(points, points), np.arange(len(points)))


def test_region_helpers_match_blender_topology():
    clear_scene()
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=7, y_subdivisions=5)  # quads
    bpy.ops.mesh.primitive_cone_add(vertices=9)  # triangles + 9-gon
    for ob in list(bpy.data.objects):
        mesh = ob.data
        rng = np.random.default_rng(len(mesh.vertices))
        mask = rng.random(len(mesh.vertices)) < 0.6
        ev = np.array([tuple(e.vertices) for e in mesh.edges])
        lv = np.array([lp.vertex_index for lp in mesh.loops])
        start = np.array([p.loop_start for p in mesh.polygons])
        total = np.array([p.loop_total for p in mesh.polygons])
        assert mesh_data.edges_in_region(ev, mask).tolist() == [all(mask[list(e.vertices)]) for e in mesh.edges]
        assert mesh_data.polygons_in_region(lv, start, total, mask).tolist() == [all(mask[list(p.vertices)]) for p in mesh.polygons]


def test_read_object_world_space_and_triangles():
    full, part = scene_pair()
    v, f, remap = operators.read_object(bpy.context, part, use_modifiers=True)
    assert remap is None
    assert np.abs(v - PART_V_MOVED).max() < 1e-5 * np.abs(PART_V_MOVED).max()
    assert np.array_equal(np.sort(np.sort(f, axis=1), axis=0), np.sort(np.sort(PART_F, axis=1), axis=0))
    # a topology-changing modifier: results are mapped back to the original vertices
    full.modifiers.new("sub", 'SUBSURF').levels = 1
    v, f, remap = operators.read_object(bpy.context, full, use_modifiers=True)
    assert len(v) > len(FULL_V) and remap is not None and len(remap) == len(FULL_V)
    # subdivision keeps (smoothed) original vertices first: each maps near itself
    assert np.linalg.norm(v[remap] - FULL_V, axis=1).max() < 0.1


def test_fingerprint_follows_mesh_transform_and_options():
    """The cache key of a prepared shape: equal for the same world mesh and options, different
    after moving a vertex, moving the object, or changing an option."""
    full, _ = scene_pair()
    options = {"k": 10, "mode": "dual", "alpha": 0.33}

    def digest(**changed):
        v, f, _ = operators.read_object(bpy.context, full, use_modifiers=True)
        return cache_module.fingerprint(v, f, dict(options, **changed))

    first = digest()
    assert digest() == first
    assert digest(k=11) != first and digest(mode="lbo") != first
    full.data.vertices[5].co.x += 1e-3
    full.data.update()
    moved_vertex = digest()
    assert moved_vertex != first
    full.location.x += 1.0
    bpy.context.view_layer.update()
    assert digest() not in (first, moved_vertex)


def test_cache_keeps_the_latest_per_key_and_evicts_the_oldest():
    c = cache_module.LocalizerCache(capacity=2)
    c.put("a", "1", "La")
    assert c.get("a", "1") == "La" and c.get("a", "2") is None and c.get("b", "1") is None
    c.put("a", "2", "La2")
    assert c.get("a", "1") is None and c.get("a", "2") == "La2" and len(c) == 1
    c.put("b", "1", "Lb")
    c.get("a", "2")  # a is now the most recent
    c.put("c", "1", "Lc")
    assert c.get("b", "1") is None and c.get("a", "2") == "La2" and c.get("c", "1") == "Lc"
    assert (c.builds, c.hits) == (4, 5)
    c.clear()
    assert len(c) == 0


# ---------------------------------------------------------------------------------------------
# tests: the worker job (the modal operator's background path) with the real library


def test_job_thread_reports_progress_and_cancels():
    seen = []
    job = job_module.LocalizeJob(dualspectra, FULL_V, FULL_F, PART_V_MOVED, PART_F, LIB_OPTIONS,
                                 on_progress=lambda f, s: seen.append(f))
    job.start()
    t0 = time.monotonic()
    while job.progress()[2] == 0 and not job.done and time.monotonic() - t0 < 120:
        time.sleep(0.01)  # the main thread keeps running while the worker computes
    assert not job.done or job.error is None, f"failed before the first progress report: {job.error!r}"
    job.cancel()
    assert job.wait(120), "worker did not stop within 120 s of the cancel request"
    assert job.cancelled and job.result is None and job.error is None, (job.cancelled, job.error)
    assert seen and all(0.0 <= f <= 1.0 for f in seen), seen


def test_job_reuses_a_given_localizer():
    """With a prepared Localizer the job only locates (its progress spans the whole bar) and
    gives what the Localizer gives directly."""
    options = dict(LIB_OPTIONS, plane_cuts=2, max_iterations=10)
    localizer = dualspectra.Localizer(FULL_V, FULL_F, **options)
    seen = []
    job = job_module.LocalizeJob(dualspectra, None, None, PART_V_MOVED, PART_F, options, localizer=localizer,
                                 on_progress=lambda f, s: seen.append((f, s)))
    job.run()
    assert job.error is None and job.reused and job.localizer is localizer and job.phase == "partial", job.error
    assert seen[0] == (0.0, "preprocessing") and seen[-1][0] == 1.0, seen[:2]
    direct = localizer.locate(PART_V_MOVED, PART_F)
    assert np.array_equal(job.result.region, direct.region)


# ---------------------------------------------------------------------------------------------
# tests: the operator

RESULT = {}
LIB_OPTIONS = dict(k=ARGS.k, max_iterations=ARGS.max_iterations)
OP_OPTIONS = dict(LIB_OPTIONS, time_limit=ARGS.time_limit)


def run_localize(**kw):
    t0 = time.monotonic()
    ret = bpy.ops.dualspectra.localize(**OP_OPTIONS, **kw)
    return ret, time.monotonic() - t0


def test_operator_selects_the_cut_region():
    full, part = scene_pair()
    with captured_output() as out:
        ret, seconds = run_localize(partial_object="")  # default: the other selected mesh
    assert ret == {'FINISHED'}, ret
    reported = re.search(r"Selected \d+ of \d+ vertices .*\(confidence ([0-9.]+),", out["text"])
    assert reported and 0.0 <= float(reported.group(1)) <= 1.0, out["text"]
    RESULT["confidence"] = reported.group(1)
    optimised_on = re.search(r"optimised on (\d+) vertices", out["text"])
    assert optimised_on and int(optimised_on.group(1)) > 0, out["text"]
    RESULT["optimisation_vertices"] = int(optimised_on.group(1))
    mesh = full.data
    sel = selected_vertices(mesh)
    score = np.zeros(len(mesh.vertices), dtype=np.float32)
    mesh.attributes["dualspectra_score"].data.foreach_get("value", score)
    region_attr = np.zeros(len(mesh.vertices), dtype=bool)
    mesh.attributes["dualspectra_region"].data.foreach_get("value", region_attr)
    assert "dualspectra_color" in mesh.attributes
    value = iou(sel, TRUTH)
    precision = (sel & TRUTH).sum() / max(1, sel.sum())
    recall = (sel & TRUTH).sum() / TRUTH.sum()
    print(f"    operator: {seconds:.1f} s, {sel.sum()} selected, IoU {value:.3f}, precision {precision:.3f}, recall {recall:.3f}")
    RESULT["selection"] = sel
    assert np.array_equal(region_attr, sel)
    assert np.all((score >= 0) & (score <= 1))
    edges = np.array([tuple(e.vertices) for e in mesh.edges])
    assert [e.select for e in mesh.edges] == (sel[edges[:, 0]] & sel[edges[:, 1]]).tolist()
    assert [p.select for p in mesh.polygons] == [bool(sel[list(p.vertices)].all()) for p in mesh.polygons]
    assert value >= ARGS.min_iou, f"IoU {value:.3f} < {ARGS.min_iou}"


@contextlib.contextmanager
def captured_output():
    """Collect what Blender prints to file descriptor 1 (its report lines, e.g.
    ``Warning: ...`` in background mode) into ``out["text"]``."""
    libc = ctypes.CDLL(None)
    sys.stdout.flush()
    libc.fflush(None)
    saved = os.dup(1)
    out = {}
    with tempfile.TemporaryFile() as tmp:
        os.dup2(tmp.fileno(), 1)
        try:
            yield out
        finally:
            sys.stdout.flush()
            libc.fflush(None)
            os.dup2(saved, 1)
            os.close(saved)
            tmp.seek(0)
            out["text"] = tmp.read().decode("utf-8", "replace")
            sys.stdout.write(out["text"])


def test_loose_vertex_and_degenerate_face_are_left_to_the_library():
    """The add-on hands Blender's arrays over as they are: a loose vertex and a zero-area
    triangle (two coincident corners) on new vertices are left out by the library, which says
    so (reported as a warning), and the selection covers every vertex of the object: the
    original ones exactly as without the extra elements, the extra ones unselected."""
    if "selection" not in RESULT:
        raise Skip("needs test_operator_selects_the_cut_region")
    n = len(FULL_V)
    extra_v = np.array([[5.0, 5.0, 5.0], [6.0, 5.0, 5.0], [6.0, 6.0, 5.0], [6.0, 5.0, 5.0]])
    clear_scene()
    full = make_object("Full", np.r_[FULL_V, extra_v], np.r_[FULL_F, [[n + 1, n + 2, n + 3]]], FULL_MATRIX)
    part = make_object("Partial", PART_V_MOVED, PART_F, PART_MATRIX)
    select_only(full, part, active=full)
    assert len(full.data.vertices) == n + 4 and len(full.data.polygons) == len(FULL_F) + 1, "Blender kept the extras"
    with captured_output() as out, warnings.catch_warnings(record=True) as printed:
        ret, _ = run_localize(partial_object="")
    assert ret == {'FINISHED'}, ret
    assert "full mesh: left out 1 degenerate face(s) and 4 vertex(es)" in out["text"], out["text"]
    # Reported once: the add-on silences the library's Python warning for its own calls only.
    assert not [w for w in printed if issubclass(w.category, dualspectra.DualspectraWarning)], printed
    with warnings.catch_warnings(record=True) as printed:
        warnings.simplefilter("default")
        dualspectra.Localizer(np.r_[FULL_V, extra_v], np.r_[FULL_F, [[n + 1, n + 2, n + 3]]], resolution=0, plane_cuts=2)
    assert [issubclass(w.category, dualspectra.DualspectraWarning) for w in printed] == [True], printed
    sel = selected_vertices(full.data)
    assert len(sel) == n + 4 and not sel[n:].any()
    assert np.array_equal(sel[:n], RESULT["selection"]), f"differ on {(sel[:n] != RESULT['selection']).sum()} vertices"


def test_non_manifold_partial_is_split_and_said_so():
    """A fin on an edge inside the part (one more triangle, on a new last vertex: three
    triangles on that edge) is split off by the library's intake, which says so (reported as
    warnings: the split, and the fin left out as a separate piece); the part is then the part
    as it was, so the selection is the one without the fin."""
    if "selection" not in RESULT:
        raise Skip("needs test_operator_selects_the_cut_region")
    count = {}
    for t in PART_F:
        for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            key = (min(e), max(e))
            count[key] = count.get(key, 0) + 1
    a, b = next(k for k, c in count.items() if c == 2)  # an edge inside the part
    n = len(PART_V_MOVED)
    tip = (PART_V_MOVED[a] + PART_V_MOVED[b]) / 2 + (0.0, 0.0, 0.2)
    clear_scene()
    full = make_object("Full", FULL_V, FULL_F, FULL_MATRIX)
    fin = make_object("Fin", np.r_[PART_V_MOVED, [tip]], np.r_[PART_F, [[a, b, n]]], PART_MATRIX)
    select_only(full, fin, active=full)
    assert len(fin.data.polygons) == len(PART_F) + 1, "Blender kept the fin"
    with captured_output() as out:
        ret, _ = run_localize(partial_object="Fin")
    assert ret == {'FINISHED'}, ret
    said = "partial mesh: split 1 non-manifold edge(s) and 2 non-manifold vertex(es) (2 vertex copies"
    assert said in out["text"], out["text"]
    assert f"only its largest component ({n} of {n + 3} vertices)" in out["text"], out["text"]
    sel = selected_vertices(full.data)
    assert np.array_equal(sel, RESULT["selection"]), f"differ on {(sel != RESULT['selection']).sum()} vertices"


def test_two_parts_on_one_object_reuse_the_prepared_shape():
    """Locating a second part on the same full object reuses its prepared Localizer, and each
    selection is the one a fresh preparation gives."""
    full, part = scene_pair()
    other_v, other_f, _ = cut_by_plane(FULL_V, FULL_F, (-0.2, -1.0, 0.3), 0.3)
    other = make_object("Other", rigid(other_v, (0.3, 0.2, -1.0), (2.0, -3.0, 0.0)), other_f, PART_MATRIX)
    select_only(full, active=full)
    cache = cache_module.CACHE

    def locate(ob):
        builds, hits = cache.builds, cache.hits
        with captured_output() as out:
            ret, seconds = run_localize(partial_object=ob.name)
        assert ret == {'FINISHED'}, ret
        reused = (cache.builds - builds, cache.hits - hits) == (0, 1)
        assert reused or (cache.builds - builds, cache.hits - hits) == (1, 0)
        assert ("prepared shape reused" in out["text"]) == reused, out["text"]
        print(f"    {ob.name}: {seconds:.1f} s, {'reused' if reused else 'prepared'}")
        return selected_vertices(full.data), reused

    cache.clear()
    first_fresh, reused = locate(part)
    assert not reused
    other_cached, reused = locate(other)
    assert reused, "the second part prepared the full shape again"
    first_cached, reused = locate(part)
    assert reused
    cache.clear()
    other_fresh, reused = locate(other)
    assert not reused
    assert np.array_equal(first_cached, first_fresh), f"differ on {(first_cached != first_fresh).sum()} vertices"
    assert np.array_equal(other_cached, other_fresh), f"differ on {(other_cached != other_fresh).sum()} vertices"
    assert not np.array_equal(first_fresh, other_fresh), "two different parts gave one selection"
    # A changed option prepares anew.
    builds = cache.builds
    ret, _ = run_localize(partial_object=part.name, **{"plane_cuts": 5})
    assert ret == {'FINISHED'} and cache.builds == builds + 1


def world_arrays(ob):
    """World positions ``matrix_world @ co`` (float32 ``co`` as Blender stores them) and triangles,
    read with the plain bpy API."""
    me = ob.data
    co = np.array([tuple(v.co) for v in me.vertices], dtype=np.float32).astype(np.float64)
    # the evaluated transform (recomposed from location/rotation/scale), as the scene shows it
    m = np.array(ob.evaluated_get(bpy.context.evaluated_depsgraph_get()).matrix_world, dtype=np.float64)
    if hasattr(me, "calc_loop_triangles"):
        me.calc_loop_triangles()
    tris = np.array([tuple(t.vertices) for t in me.loop_triangles], dtype=np.int64)
    return co @ m[:3, :3].T + m[:3, 3], tris


def test_operator_equals_direct_call_in_world_space():
    """The operator's selection is the library's region for the meshes as they are in world
    space, whatever the object transforms (here different, one with non-uniform scale)."""
    if "selection" not in RESULT:
        raise Skip("needs test_operator_selects_the_cut_region")
    full, part = scene_pair()
    fv, ff = world_arrays(full)
    pv, pf = world_arrays(part)
    assert np.abs(fv - FULL_V).max() < 1e-5 * np.abs(FULL_V).max()
    assert np.abs(pv - PART_V_MOVED).max() < 1e-5 * np.abs(PART_V_MOVED).max()
    res = dualspectra.localize(fv, ff, pv, pf, mode="dual", alpha=0.33, **LIB_OPTIONS)
    direct = np.asarray(res.region, dtype=bool)
    # Same options and (to float32) inputs: the same region. (2-7 of 642 vertices used to
    # differ: the operator passed its single-precision alpha, 0.33000001311302185; the add-on
    # now passes the decimal the property stands for, schema.option_values.)
    diff = int((direct != RESULT["selection"]).sum())
    print(f"    direct call differs on {diff} vertices, IoU {iou(direct, RESULT['selection']):.4f}")
    assert diff == 0, f"differ on {diff} vertices"
    assert f"{res.confidence:.2f}" == RESULT["confidence"], (res.confidence, RESULT["confidence"])
    assert res.optimisation_vertices == RESULT["optimisation_vertices"], (res.optimisation_vertices, RESULT)


def test_invoke_in_edit_mode_headless():
    """Without a window, INVOKE falls back to the foreground path; edit mode is kept and the
    edit-mode selection is the region; one undo step restores the previous selection."""
    if "selection" not in RESULT:
        raise Skip("needs test_operator_selects_the_cut_region")
    full, part = scene_pair()
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='DESELECT')
    ret = bpy.ops.dualspectra.localize('INVOKE_DEFAULT', partial_object=part.name, **OP_OPTIONS)
    assert ret == {'FINISHED'}, ret
    assert full.mode == 'EDIT'
    import bmesh

    bm = bmesh.from_edit_mesh(full.data)
    sel = np.array([v.select for v in bm.verts])
    assert np.array_equal(sel, RESULT["selection"]), f"differ on {(sel != RESULT['selection']).sum()} vertices"
    bpy.ops.object.mode_set(mode='OBJECT')


def test_operator_is_one_undo_step():
    """Registered with UNDO (one undo step, redo panel). Undo itself cannot be exercised
    headless: ed.undo's poll needs a window."""
    rna = bpy.types.DUALSPECTRA_OT_localize.bl_rna
    assert {'REGISTER', 'UNDO'} <= set(bpy.types.DUALSPECTRA_OT_localize.bl_options), rna


def expect_operator_error(words, **kw):
    """bpy.ops raises RuntimeError when the operator reported an ERROR (it returned CANCELLED)."""
    try:
        ret = bpy.ops.dualspectra.localize(**kw)
    except RuntimeError as exc:
        assert all(w in str(exc) for w in words), f"{exc} lacks {words}"
        return str(exc)
    raise AssertionError(f"no error reported; returned {ret}")


def test_error_partial_without_faces():
    full, _ = scene_pair()
    mesh = bpy.data.meshes.new("Edges")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(0, 1), (1, 2)], [])
    ob = bpy.data.objects.new("Edges", mesh)
    bpy.context.scene.collection.objects.link(ob)
    full.data.vertices.foreach_set("select", np.zeros(len(full.data.vertices), dtype=bool))
    msg = expect_operator_error(["no faces", "Edges"], partial_object="Edges")
    print("    reported:", msg.strip())
    assert selected_vertices(full.data).sum() == 0 and "dualspectra_score" not in full.data.attributes


def test_error_no_partial_chosen():
    full, _ = scene_pair()
    select_only(full, active=full)
    expect_operator_error(["select"], partial_object="")
    expect_operator_error(["active"], partial_object="Full")
    expect_operator_error(["no object"], partial_object="Nope")


def test_error_closed_partial_reported_by_library():
    """A partial that no intake can make a part of anything (a closed octahedron: no boundary,
    so no Dirichlet spectrum): the library's message, reported, not raised; nothing written."""
    full, _ = scene_pair()
    v = [(0.3, 0, 0), (-0.3, 0, 0), (0, 0.3, 0), (0, -0.3, 0), (0, 0, 0.3), (0, 0, -0.3)]
    f = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    make_object("Closed", np.array(v, dtype=np.float64), f, PART_MATRIX)
    msg = expect_operator_error(["Localization failed on 'Closed'", "the partial shape has no boundary"],
                                partial_object="Closed", **OP_OPTIONS)
    print("    reported:", msg.strip())
    assert "dualspectra_score" not in full.data.attributes


def test_error_time_limit():
    full, part = scene_pair()
    expect_operator_error(["time limit"], partial_object=part.name, time_limit=1e-3, **LIB_OPTIONS)
    assert "dualspectra_score" not in full.data.attributes


def test_options_reach_the_library():
    """The option properties are passed to the library, which checks what Blender's ranges
    cannot express: resolution 50 is inside 0..200000 but too coarse (0 or at least 200)."""
    full, part = scene_pair()
    expect_operator_error(["resolution = 50 is too coarse"], partial_object=part.name, resolution=50, **OP_OPTIONS)
    assert "dualspectra_score" not in full.data.attributes


# ---------------------------------------------------------------------------------------------
# tests: the search (the partial active, the candidates selected)

#: Other models than the full shape: differently bumped and stretched surfaces.
DECOYS = {
    "Decoy A": ([((0.2, -1.0, 0.3), 0.6, 0.1), ((1.0, 0.5, -0.5), 0.4, 0.3)], (1.0, 1.2, 0.9)),
    "Decoy B": ([((0.0, 0.0, 1.0), 0.9, 0.05), ((0.0, 0.0, -1.0), 0.9, 0.05)], (0.8, 0.8, 1.2)),
}
#: Lighter than LIB_OPTIONS (three shapes per search; the right one still ranks first by a margin).
SEARCH_OPTIONS = dict(k=6, max_iterations=10, plane_cuts=2, resolution=0)


def decoy_meshes():
    return [lumpy_surface(ARGS.subdivisions, bumps, stretch) for bumps, stretch in DECOYS.values()]


def search_scene():
    """The full shape between two decoys (own transforms), the partial active."""
    clear_scene()
    full = make_object("Full", FULL_V, FULL_F, FULL_MATRIX)
    decoys = [make_object(name, v, f, affine((4.0 * i - 2.0, -4.0, 0.0), (0.0, 0.0, 0.5 * i), (1.0, 1.0, 1.0)))
              for i, (name, (v, f)) in enumerate(zip(DECOYS, decoy_meshes()))]
    part = make_object("Partial", PART_V_MOVED, PART_F, PART_MATRIX)
    select_only(decoys[0], full, decoys[1], part, active=part)
    return full, decoys, part


def run_search(**kw):
    t0 = time.monotonic()
    ret = bpy.ops.dualspectra.search(**dict(SEARCH_OPTIONS, time_limit=ARGS.time_limit, **kw))
    return ret, time.monotonic() - t0


def test_search_job_ranks_the_source_first_and_reuses_a_given_shape():
    """bpy-free: the search job prepares the candidates it is not given, keeps them, and ranks
    the shape the partial was cut from first, with the region its Localizer gives."""
    localizer = dualspectra.Localizer(FULL_V, FULL_F, **SEARCH_OPTIONS)
    (av, af), (bv, bf) = decoy_meshes()
    seen = []
    job = job_module.SearchJob(dualspectra, PART_V_MOVED, PART_F, [(av, af, None), (FULL_V, FULL_F, localizer), (bv, bf, None)],
                               SEARCH_OPTIONS, on_progress=lambda f, s: seen.append(f))
    job.run()
    assert job.error is None and not job.cancelled, job.error
    order = [(m.index, round(m.score, 4)) for m in job.result]
    print(f"    ranking (index, score): {order}")
    assert order[0][0] == 1 and sorted(i for i, _ in order) == [0, 1, 2], order
    assert job.reused == [False, True, False] and job.localizers[1] is localizer
    assert all(isinstance(loc, dualspectra.Localizer) for loc in job.localizers)
    assert seen == sorted(seen) and seen[0] < 0.5 and seen[-1] == 1.0, seen[:3]
    assert np.array_equal(job.result[0].localization.region, localizer.locate(PART_V_MOVED, PART_F).region)
    # Cancelled at its first report.
    job = job_module.SearchJob(dualspectra, PART_V_MOVED, PART_F, [(av, af, None), (bv, bf, None)], SEARCH_OPTIONS)
    job.start()
    job.cancel()
    assert job.wait(120) and job.cancelled and job.result is None and job.error is None, job.error


def test_search_operator_ranks_the_selected_objects_and_selects_on_the_best():
    full, decoys, part = search_scene()
    assert bpy.ops.dualspectra.search.poll()
    cache_module.CACHE.clear()
    with captured_output() as out:
        ret, seconds = run_search()
    assert ret == {'FINISHED'}, ret
    text = out["text"]
    assert "Best match for 'Partial': 'Full'" in text and "(3 prepared, 0 reused)" in text, text
    assert "#1 'Full': score" in text and "#2 'Decoy" in text and "#3 'Decoy" in text, text
    rank, similarity = operators.RANK_PROPERTY, operators.SIMILARITY_PROPERTY
    assert full[rank] == 1 and sorted(d[rank] for d in decoys) == [2, 3]
    assert full[similarity] < min(d[similarity] for d in decoys)
    sel = selected_vertices(full.data)
    print(f"    search: {seconds:.1f} s, scores {[round(ob[similarity], 4) for ob in [full] + decoys]}, "
          f"IoU {iou(sel, TRUTH):.3f} with the cut")
    # The library's answer for the meshes in world space, with the same options.
    fv, ff = world_arrays(full)
    pv, pf = world_arrays(part)
    direct = dualspectra.Localizer(fv, ff, **SEARCH_OPTIONS).locate(pv, pf)
    assert np.array_equal(sel, direct.region), f"differ on {(sel != direct.region).sum()} vertices"
    # The reported confidences are the search's (against the other objects), not each
    # localization's alone.
    ranked = dualspectra.search((pv, pf), [dualspectra.Localizer(*world_arrays(ob), **SEARCH_OPTIONS) for ob in [full] + decoys])
    said = [float(c) for c in re.findall(r"#\d+ '[^']+': score [0-9.e+-]+ \(confidence ([0-9.]+)\)", text)]
    assert said == [round(m.confidence, 2) for m in ranked], (said, [m.confidence for m in ranked])
    best = re.search(r"Best match for 'Partial': 'Full' \(score [0-9.e+-]+, confidence ([0-9.]+)\)", text)
    assert best and float(best.group(1)) == said[0], text
    assert all("dualspectra_region" not in d.data.attributes for d in decoys + [part])
    # Again: every prepared shape is reused, the answer is the same.
    full.data.vertices.foreach_set("select", np.zeros(len(full.data.vertices), dtype=bool))
    with captured_output() as out:
        ret, _ = run_search()
    assert ret == {'FINISHED'} and "(0 prepared, 3 reused)" in out["text"], out["text"]
    assert np.array_equal(selected_vertices(full.data), sel)


def test_search_operator_properties_and_poll():
    table = dualspectra.options_schema()
    names = {p.identifier for p in bpy.ops.dualspectra.search.get_rna_type().properties}
    assert names == {"rna_type", "time_limit", "use_modifiers", "background"} | {spec["name"] for spec in table}, names
    assert {'REGISTER', 'UNDO'} <= set(bpy.types.DUALSPECTRA_OT_search.bl_options)
    full, decoys, part = search_scene()
    select_only(part, active=part)
    assert not bpy.ops.dualspectra.search.poll()  # no candidate selected
    select_only(part, full, active=None)
    assert not bpy.ops.dualspectra.search.poll()  # no partial (active) object


def expect_search_error(words, **kw):
    try:
        ret = bpy.ops.dualspectra.search(**dict(SEARCH_OPTIONS, **kw))
    except RuntimeError as exc:
        assert all(w in str(exc) for w in words), f"{exc} lacks {words}"
        return str(exc)
    raise AssertionError(f"no error reported; returned {ret}")


def test_search_errors_name_the_object():
    full, decoys, part = search_scene()
    mesh = bpy.data.meshes.new("Edges")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(0, 1), (1, 2)], [])
    edges = bpy.data.objects.new("Edges", mesh)
    bpy.context.scene.collection.objects.link(edges)
    select_only(full, edges, part, active=part)
    msg = expect_search_error(["Search failed on 'Edges'", "no faces"])
    print("    reported:", msg.strip())
    select_only(full, part, active=part)
    expect_search_error(["time limit"], time_limit=1e-3)
    assert "dualspectra_region" not in full.data.attributes


def test_panel_offers_both_buttons():
    """The panel's draw code (with a recording stand-in for Blender's layout): both buttons,
    the search's enabled with the partial active and candidates selected, the options passed."""
    import types

    class Layout:
        def __init__(self):
            self.log, self.scale_y, self.enabled = [], 1.0, True

        def column(self):
            return self

        row = box = column

        def separator(self):
            pass

        def label(self, text="", icon='NONE'):
            self.log.append(("label", text, self.enabled))

        def prop(self, data, name):
            self.log.append(("prop", name, self.enabled))

        def operator(self, idname, icon='NONE'):
            op = types.SimpleNamespace()
            self.log.append(("operator", idname, self.enabled, op))
            return op

    panel_class = sys.modules[ADDON + ".panel"].VIEW3D_PT_dualspectra
    full, decoys, part = search_scene()
    layout = Layout()
    panel_class.draw(types.SimpleNamespace(layout=layout), bpy.context)
    ops = {entry[1]: entry for entry in layout.log if entry[0] == "operator"}
    assert set(ops) == {"dualspectra.localize", "dualspectra.search"}, layout.log
    assert ops["dualspectra.search"][2] and ops["dualspectra.search"][3].k == bpy.context.scene.dualspectra.k
    assert ("label", "Search: is 'Partial' part of one of 3 selected meshes?", True) in layout.log, layout.log
    select_only(part, active=part)
    layout = Layout()
    panel_class.draw(types.SimpleNamespace(layout=layout), bpy.context)
    assert not [e for e in layout.log if e[0] == "operator" and e[1] == "dualspectra.search"][0][2], layout.log


def test_poll_needs_active_mesh():
    clear_scene()
    bpy.ops.object.empty_add()
    assert not bpy.ops.dualspectra.localize.poll()


def test_disable_and_enable_again():
    """Unregistering removes the operator, the scene settings, the load handler and the warning
    filter and empties the cache; registering again builds the option properties anew."""
    import addon_utils

    def quieting_filters():
        return [f for f in warnings.filters if f[2] is dualspectra.DualspectraWarning and f[0] == "ignore"]

    assert len(quieting_filters()) == 1
    cache_module.CACHE.put("x", "y", object())
    addon_utils.disable(ADDON, default_set=True)
    assert not hasattr(bpy.types, "DUALSPECTRA_OT_localize") and not hasattr(bpy.types.Scene, "dualspectra")
    assert not hasattr(bpy.types, "DUALSPECTRA_OT_search")
    assert len(cache_module.CACHE) == 0 and not quieting_filters()
    assert not any(getattr(h, "__name__", "") == "clear_cache" for h in bpy.app.handlers.load_pre)
    addon_utils.enable(ADDON, default_set=True)
    for op in (bpy.ops.dualspectra.localize, bpy.ops.dualspectra.search):
        props = op.get_rna_type().properties
        assert all(spec["name"] in props for spec in dualspectra.options_schema())
    assert sum(getattr(h, "__name__", "") == "clear_cache" for h in bpy.app.handlers.load_pre) == 1
    assert len(quieting_filters()) == 1


# ---------------------------------------------------------------------------------------------


class Skip(Exception):
    pass


def main():
    tests = [(n, f) for n, f in globals().items() if n.startswith("test_") and callable(f)]
    if ARGS.only:
        wanted = set(ARGS.only.split(","))
        tests = [(n, f) for n, f in tests if n in wanted]
    failed = []
    for name, fn in tests:
        t0 = time.monotonic()
        try:
            fn()
        except Skip as exc:
            print(f"SKIP {name}: {exc}")
            continue
        except BaseException:
            failed.append(name)
            print(f"FAIL {name} ({time.monotonic() - t0:.1f} s)")
            traceback.print_exc()
            continue
        print(f"ok   {name} ({time.monotonic() - t0:.1f} s)")
    print(f"{len(tests) - len(failed)} of {len(tests)} passed" + (f"; failed: {', '.join(failed)}" if failed else ""))
    sys.stdout.flush()
    if failed:
        sys.exit(1)


main()
