"""The Localize operator: read two Blender meshes, run dualspectra, write the region.

Read, check, write (glTF-Blender-IO's operator habit):

* read: both objects' evaluated meshes (modifiers applied), triangulated with
  ``loop_triangles``, in world space (``matrix_world @ co``), via ``mesh_data``;
* check: errors become ``self.report({'ERROR'}, ...)`` and ``{'CANCELLED'}``;
* write: the region's vertices, and the edges and faces between them, are selected on
  the active object; the soft score is stored as the point attribute
  ``dualspectra_score``, the region as ``dualspectra_region`` and a colour ramp of the
  score as the colour attribute ``dualspectra_color``. One undo step.

``invoke`` (a click in the interface) runs the localizer on a worker thread and polls it
from a modal timer: progress in the status bar and the window manager's progress
cursor, Esc cancels. ``execute`` (scripts, ``blender -b``, the redo panel) runs it in
the foreground: there is no event loop for modal timers without a window.
"""

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

from . import library, mesh_data
from .job import LocalizeJob

MODES = (
    ('DUAL', "Dual", "k Laplace-Beltrami + k scale-invariant eigenvalues (the paper's method)"),
    ('LBO', "LBO", "2k Laplace-Beltrami eigenvalues only"),
    ('SI', "Scale-invariant", "2k scale-invariant eigenvalues only"),
)

SCORE_ATTRIBUTE = "dualspectra_score"
REGION_ATTRIBUTE = "dualspectra_region"
COLOR_ATTRIBUTE = "dualspectra_color"


class UserError(Exception):
    """A problem the user can fix (wrong selection, missing faces): reported, not raised."""


# -- choosing the partial object -----------------------------------------------------------------

def default_partial(context):
    """The other selected mesh object when exactly one is selected besides the active one."""
    active = context.active_object
    others = [ob for ob in context.selected_objects if ob is not active and ob.type == 'MESH']
    return others[0] if len(others) == 1 else None


def resolve_partial(context, name):
    """The partial object: ``name`` if given, else the scene setting, else the other selected mesh."""
    active = context.active_object
    if name:
        ob = bpy.data.objects.get(name)
        if ob is None:
            raise UserError(f"no object named '{name}'")
    else:
        settings = getattr(context.scene, "dualspectra", None)
        ob = settings.partial if settings is not None and settings.partial is not None else None
        if ob is None:
            ob = default_partial(context)
        if ob is None:
            raise UserError("choose the partial object in the panel, or select it together with the full (active) object")
    if ob.type != 'MESH':
        raise UserError(f"'{ob.name}' is not a mesh object")
    if ob is active:
        raise UserError(f"'{ob.name}' is the active (full) object; the partial object must be another mesh")
    return ob


# -- reading ---------------------------------------------------------------------------------------

def _mesh_arrays(mesh):
    """Local vertex positions ``(n, 3)`` and loop-triangle vertex indices ``(m, 3)`` of a ``bpy`` mesh."""
    n = len(mesh.vertices)
    co = np.empty(n * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    if hasattr(mesh, "calc_loop_triangles"):
        mesh.calc_loop_triangles()
    m = len(mesh.loop_triangles)
    tris = np.empty(m * 3, dtype=np.int32)
    mesh.loop_triangles.foreach_get("vertices", tris)
    return co.reshape(n, 3).astype(np.float64), tris.reshape(m, 3).astype(np.int64)


def read_object(context, ob, use_modifiers):
    """World-space :class:`mesh_data.TriangleMesh` of ``ob`` and, if a modifier changed the
    vertex count, the map from the original vertices to the evaluated ones (else ``None``)."""
    if ob.mode == 'EDIT':
        ob.update_from_editmode()
    if use_modifiers:
        depsgraph = context.evaluated_depsgraph_get()
        ob_eval = ob.evaluated_get(depsgraph)
        mesh = ob_eval.to_mesh()
        try:
            local, tris = _mesh_arrays(mesh)
        finally:
            ob_eval.to_mesh_clear()
        matrix = np.array(ob_eval.matrix_world, dtype=np.float64)
    else:
        local, tris = _mesh_arrays(ob.data)
        matrix = np.array(ob.matrix_world, dtype=np.float64)
    world = mesh_data.world_positions(local, matrix)
    tri_mesh = mesh_data.triangle_mesh(world, tris, name=ob.name)
    original_to_evaluated = None
    n_original = len(ob.data.vertices)
    if len(world) != n_original:
        co = np.empty(n_original * 3, dtype=np.float32)
        ob.data.vertices.foreach_get("co", co)
        original_world = mesh_data.world_positions(co.reshape(-1, 3), np.array(ob.matrix_world, dtype=np.float64))
        original_to_evaluated = mesh_data.nearest_indices(original_world, world)
    return tri_mesh, original_to_evaluated


# -- writing ---------------------------------------------------------------------------------------

def _replace_attribute(attributes, name, type_, domain):
    old = attributes.get(name)
    if old is not None:
        if old.data_type == type_ and old.domain == domain:
            return old
        attributes.remove(old)
    return attributes.new(name, type_, domain)


def write_result(mesh, region, score):
    """Select ``region (n,)`` on ``mesh`` (vertices, edges between them, faces inside) and store
    the score. ``mesh`` must not be in edit mode (edit-mode data would overwrite it)."""
    region = np.asarray(region, dtype=bool)
    score = np.asarray(score, dtype=np.float64)
    mesh.vertices.foreach_set("select", region)
    n_edges = len(mesh.edges)
    if n_edges:
        ev = np.empty(n_edges * 2, dtype=np.int32)
        mesh.edges.foreach_get("vertices", ev)
        mesh.edges.foreach_set("select", mesh_data.edges_in_region(ev.reshape(-1, 2), region))
    n_polys = len(mesh.polygons)
    if n_polys:
        loop_vertices = np.empty(len(mesh.loops), dtype=np.int32)
        mesh.loops.foreach_get("vertex_index", loop_vertices)
        start = np.empty(n_polys, dtype=np.int32)
        total = np.empty(n_polys, dtype=np.int32)
        mesh.polygons.foreach_get("loop_start", start)
        mesh.polygons.foreach_get("loop_total", total)
        mesh.polygons.foreach_set("select", mesh_data.polygons_in_region(loop_vertices, start, total, region))

    attr = _replace_attribute(mesh.attributes, SCORE_ATTRIBUTE, 'FLOAT', 'POINT')
    attr.data.foreach_set("value", score.astype(np.float32))
    attr = _replace_attribute(mesh.attributes, REGION_ATTRIBUTE, 'BOOLEAN', 'POINT')
    attr.data.foreach_set("value", region)
    colors = getattr(mesh, "color_attributes", mesh.attributes)
    attr = _replace_attribute(colors, COLOR_ATTRIBUTE, 'FLOAT_COLOR', 'POINT')
    attr.data.foreach_set("color", mesh_data.score_colors(score).astype(np.float32).ravel())
    try:
        mesh.color_attributes.active_color = attr
    except (AttributeError, TypeError):
        pass
    mesh.update()


# -- the operator ----------------------------------------------------------------------------------

class DUALSPECTRA_OT_localize(bpy.types.Operator):
    """Find the region of the active mesh that the partial mesh is, and select it"""

    bl_idname = "dualspectra.localize"
    bl_label = "Localize Partial Shape"
    bl_options = {'REGISTER', 'UNDO'}

    partial_object: StringProperty(
        name="Partial",
        description="Mesh object that is a (deformed) part of the active object. "
        "Empty: the panel's choice, else the other selected mesh",
    )
    mode: EnumProperty(name="Mode", items=MODES, default='DUAL')
    k: IntProperty(name="k", description="Eigenvalues per spectrum", default=20, min=1, max=200, soft_max=60)
    alpha: FloatProperty(name="Alpha", description="Exponent of the scale-invariant metric", default=0.33, min=0.0, max=1.0)
    seed: IntProperty(name="Seed", description="Seed of every random choice", default=0, min=0)
    centers: IntProperty(
        name="Start Centres",
        description="Farthest-point centres of the starts, 3 starts each (0: library default, 4)",
        default=0, min=0, soft_max=20,
    )
    max_iterations: IntProperty(
        name="Iterations",
        description="Trust-region iterations per start (0: library default, 25)",
        default=0, min=0, soft_max=200,
    )
    spectral_cuts: IntProperty(
        name="Spectral Cuts",
        description="Further starts from the full shape's first N eigenfunctions, 2 each: the region on either "
        "side of a level set with the partial's area (for a part cut across a natural axis, e.g. a half body; "
        "0: none)",
        default=0, min=0, soft_max=8,
    )
    plane_cuts: IntProperty(
        name="Plane Cuts",
        description="Further starts, one per direction: the side of a plane with the partial's area, normal to the "
        "first N of 26 directions (6: both ways along the principal axes; 14: and the diagonals; 0: none; "
        "-1: library default, 6)",
        default=-1, min=-1, soft_max=26,
    )
    time_limit: FloatProperty(
        name="Time Limit",
        description="Stop with an error after this many seconds (0: no limit)",
        default=0.0, min=0.0, subtype='TIME', unit='TIME_ABSOLUTE',
    )
    use_modifiers: BoolProperty(name="Use Modifiers", description="Use the evaluated meshes (modifiers applied)", default=True)
    background: BoolProperty(
        name="Run in Background",
        description="When started from the interface, compute on a worker thread (Esc cancels)",
        default=True,
        options={'SKIP_SAVE'},
    )

    @classmethod
    def poll(cls, context):
        ob = context.active_object
        if ob is None or ob.type != 'MESH':
            if hasattr(cls, "poll_message_set"):
                cls.poll_message_set("The active object must be a mesh (the full shape)")
            return False
        return True

    def draw(self, context):
        layout = self.layout
        layout.prop_search(self, "partial_object", bpy.data, "objects")
        layout.prop(self, "mode")
        layout.prop(self, "k")
        layout.prop(self, "alpha")
        layout.prop(self, "seed")
        layout.prop(self, "centers")
        layout.prop(self, "max_iterations")
        layout.prop(self, "spectral_cuts")
        layout.prop(self, "plane_cuts")
        layout.prop(self, "time_limit")
        layout.prop(self, "use_modifiers")

    # read and check; returns the job (not started) or raises UserError / ImportError / MeshDataError
    def _prepare(self, context, on_progress):
        module = library.load()
        full = context.active_object
        partial = resolve_partial(context, self.partial_object)
        self.partial_object = partial.name  # the redo panel repeats the same pair
        full_mesh, original_to_evaluated = read_object(context, full, self.use_modifiers)
        partial_mesh, _ = read_object(context, partial, self.use_modifiers)
        self._full_name = full.name
        self._n_original = len(full.data.vertices)
        self._full_mesh = full_mesh
        self._original_to_evaluated = original_to_evaluated
        # Optional tuning, passed only when set so the library's defaults apply otherwise.
        tuning = {
            name: getattr(self, name)
            for name in ("centers", "max_iterations", "spectral_cuts")
            if getattr(self, name) > 0
        }
        if self.plane_cuts >= 0:  # 0 is meaningful here (no plane cuts); -1 is the default
            tuning["plane_cuts"] = self.plane_cuts
        return LocalizeJob(
            module,
            full_mesh.vertices,
            full_mesh.faces,
            partial_mesh.vertices,
            partial_mesh.faces,
            on_progress=on_progress,
            time_limit=self.time_limit,
            mode=self.mode.lower(),
            k=self.k,
            alpha=self.alpha,
            seed=self.seed,
            **tuning,
        )

    def _start(self, context, on_progress=None):
        try:
            return self._prepare(context, on_progress)
        except (UserError, mesh_data.MeshDataError, ImportError) as exc:
            self.report({'ERROR'}, str(exc))
            return None

    def _finish(self, context, job):
        if job.timed_out:
            self.report({'ERROR'}, f"Localization stopped: time limit of {self.time_limit:g} s exceeded")
            return {'CANCELLED'}
        if job.cancelled:
            self.report({'WARNING'}, "Localization cancelled")
            return {'CANCELLED'}
        if job.error is not None:
            exc = job.error
            self.report({'ERROR'}, f"Localization failed: {type(exc).__name__}: {exc}")
            return {'CANCELLED'}
        result = job.result
        full = bpy.data.objects.get(self._full_name)
        if full is None or full.type != 'MESH' or len(full.data.vertices) != self._n_original:
            self.report({'ERROR'}, f"'{self._full_name}' was deleted or edited during the localization; nothing written")
            return {'CANCELLED'}
        region = self._full_mesh.to_source(np.asarray(result.region, dtype=bool), False)
        score = self._full_mesh.to_source(np.asarray(result.score, dtype=np.float64), 0.0)
        if self._original_to_evaluated is not None:
            region = region[self._original_to_evaluated]
            score = score[self._original_to_evaluated]
        in_edit_mode = full.mode == 'EDIT'
        if in_edit_mode:
            bpy.ops.object.mode_set(mode='OBJECT')
        write_result(full.data, region, score)
        if in_edit_mode:
            bpy.ops.object.mode_set(mode='EDIT')
        self.report(
            {'INFO'},
            f"Selected {int(region.sum())} of {len(region)} vertices of '{full.name}' "
            f"(cost {float(result.cost):.3g}, {job.elapsed:.1f} s)",
        )
        return {'FINISHED'}

    # foreground: scripts, headless runs, the redo panel
    def execute(self, context):
        wm = context.window_manager
        job = self._start(context, on_progress=lambda fraction, stage: wm.progress_update(int(round(100 * fraction))))
        if job is None:
            return {'CANCELLED'}
        wm.progress_begin(0, 100)
        try:
            job.run()
        finally:
            wm.progress_end()
        return self._finish(context, job)

    # interface: worker thread + modal timer
    def invoke(self, context, event):
        if not self.background or context.window is None or bpy.app.background:
            return self.execute(context)
        job = self._start(context)
        if job is None:
            return {'CANCELLED'}
        self._job = job
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.modal_handler_add(self)
        wm.progress_begin(0, 100)
        job.start()
        self._show_progress(context)
        return {'RUNNING_MODAL'}

    def _show_progress(self, context):
        fraction, stage, _ = self._job.progress()
        context.window_manager.progress_update(int(round(100 * fraction)))
        what = "cancelling" if self._job.cancel_requested else f"{stage} {100 * fraction:.0f}%"
        context.workspace.status_text_set(f"dualspectra: {what}, {self._job.elapsed:.0f} s  (Esc to cancel)")

    def _cleanup(self, context):
        wm = context.window_manager
        if getattr(self, "_timer", None) is not None:
            wm.event_timer_remove(self._timer)
            self._timer = None
        wm.progress_end()
        context.workspace.status_text_set(None)

    def modal(self, context, event):
        if event.type == 'ESC' and event.value == 'PRESS':
            self._job.cancel()
            self._show_progress(context)
            return {'RUNNING_MODAL'}
        if event.type == 'TIMER':
            if self._job.done:
                self._cleanup(context)
                return self._finish(context, self._job)
            self._show_progress(context)
        return {'PASS_THROUGH'}

    def cancel(self, context):
        # Blender ends the modal operator (file loaded, window closed): stop the worker.
        self._job.cancel()
        self._job.wait(30.0)
        self._cleanup(context)


classes = (DUALSPECTRA_OT_localize,)
