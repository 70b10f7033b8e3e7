"""The operators: read Blender meshes, run dualspectra, write the region.

*Localize* (``dualspectra.localize``): the active object is the full shape, the partial is
another mesh; the region is selected on the active object. *Search*
(``dualspectra.search``): the active object is the partial shape and the other selected
meshes are the candidate full shapes; they are ranked by the library's similarity score
(``dualspectra.search``: lower is more similar), the ranking is reported and kept on each
candidate as the custom properties ``dualspectra_rank`` and ``dualspectra_similarity``, and
the region is selected on the best one.

Read, check, write (glTF-Blender-IO's operator habit):

* read: the objects' evaluated meshes (modifiers applied), triangulated with
  ``loop_triangles``, in world space (``matrix_world @ co``), via ``mesh_data``; the arrays
  go to the library as they are (its intake leaves out degenerate triangles and loose
  vertices, splits non-manifold edges and vertices, maps every result back to these
  vertices and says what it left out or split: reported as warnings);
* check: errors become ``self.report({'ERROR'}, ...)`` and ``{'CANCELLED'}``;
* write: the region's vertices, and the edges and faces between them, are selected on
  the full object; the soft score is stored as the point attribute
  ``dualspectra_score``, the region as ``dualspectra_region`` and a colour ramp of the
  score as the colour attribute ``dualspectra_color``. One undo step.

The library's options (``dualspectra.options_schema()``) become the operators' properties
when the add-on registers (:func:`operator_class`): labels, defaults, ranges and tooltips
are the library's. The prepared full shape (``dualspectra.Localizer``) is kept per full
object while its world-space mesh and the options are unchanged (``cache.py``), so
locating several parts on one model, or searching one set of objects for several parts,
prepares each once.

``invoke`` (a click in the interface) runs the job on a worker thread and polls it
from a modal timer: progress in the status bar and the window manager's progress
cursor, Esc cancels. ``execute`` (scripts, ``blender -b``, the redo panel) runs it in
the foreground: there is no event loop for modal timers without a window.
"""

import bpy
import numpy as np
from bpy.app.handlers import persistent
from bpy.props import BoolProperty, FloatProperty, StringProperty

from . import cache, library, mesh_data, schema
from .job import LocalizeJob, SearchJob

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
    """World-space positions ``(n, 3)`` and triangles ``(m, 3)`` of ``ob`` and, if a modifier
    changed the vertex count, the map from the original vertices to the evaluated ones (else
    ``None``)."""
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
    original_to_evaluated = None
    n_original = len(ob.data.vertices)
    if len(world) != n_original:
        if len(world) == 0:
            raise UserError(f"'{ob.name}' has no vertices after its modifiers")
        co = np.empty(n_original * 3, dtype=np.float32)
        ob.data.vertices.foreach_get("co", co)
        original_world = mesh_data.world_positions(co.reshape(-1, 3), np.array(ob.matrix_world, dtype=np.float64))
        original_to_evaluated = mesh_data.nearest_indices(original_world, world)
    return world, tris, original_to_evaluated


def cache_key(ob):
    """The key of ``ob``'s prepared shape: its session id (kept across renames), else its name."""
    return getattr(ob, "session_uid", None) or ob.name_full


@persistent
def clear_cache(*_args):
    """Forget every prepared shape (a ``load_pre`` handler: objects of another file)."""
    cache.CACHE.clear()


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


def write_region_on(ob, region, score, original_to_evaluated):
    """Write a result (indexed by the read vertices) on object ``ob``: mapped back to its
    original vertices if a modifier changed them, outside edit mode (entered again after).
    Returns the region as written."""
    region = np.asarray(region, dtype=bool)
    score = np.asarray(score, dtype=np.float64)
    if original_to_evaluated is not None:
        region = region[original_to_evaluated]
        score = score[original_to_evaluated]
    in_edit_mode = ob.mode == 'EDIT'
    if in_edit_mode:
        bpy.ops.object.mode_set(mode='OBJECT')
    write_result(ob.data, region, score)
    if in_edit_mode:
        bpy.ops.object.mode_set(mode='EDIT')
    return region


# -- the operators ---------------------------------------------------------------------------------

class JobOperator:
    """What both operators share: a job (``job.py``) run in the foreground (``execute``) or on
    a worker thread polled by a modal timer (``invoke``). Subclasses read and check in
    ``_prepare`` (returning the job, not started) and write in ``_finish``."""

    #: The library's options table this class was built from (set by :func:`operator_class`).
    options_schema = ()

    @classmethod
    def _refuse(cls, message):
        """``poll``'s ``False``, with its reason shown where Blender can (3.0+)."""
        if hasattr(cls, "poll_message_set"):
            cls.poll_message_set(message)
        return False

    def _start(self, context, on_progress=None):
        try:
            return self._prepare(context, on_progress)
        except (UserError, ImportError) as exc:
            self.report({'ERROR'}, str(exc))
            return None

    def _stopped(self, job, what):
        """Report a run that did not finish (``{'CANCELLED'}``), or ``None`` if it did."""
        if job.timed_out:
            self.report({'ERROR'}, f"{what} stopped: time limit of {self.time_limit:g} s exceeded")
            return {'CANCELLED'}
        if job.cancelled:
            self.report({'WARNING'}, f"{what} cancelled")
            return {'CANCELLED'}
        return None

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


class LocalizeOperator(JobOperator):
    """Find the region of the active mesh that the partial mesh is, and select it"""

    bl_idname = "dualspectra.localize"
    bl_label = "Localize Partial Shape"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        ob = context.active_object
        if ob is None or ob.type != 'MESH':
            return cls._refuse("The active object must be a mesh (the full shape)")
        return True

    def draw(self, context):
        layout = self.layout
        layout.prop_search(self, "partial_object", bpy.data, "objects")
        for spec in self.options_schema:
            layout.prop(self, spec["name"])
        layout.prop(self, "time_limit")
        layout.prop(self, "use_modifiers")

    # read and check; returns the job (not started) or raises UserError / ImportError
    def _prepare(self, context, on_progress):
        module = library.load()
        full = context.active_object
        partial = resolve_partial(context, self.partial_object)
        self.partial_object = partial.name  # the redo panel repeats the same pair
        full_v, full_f, original_to_evaluated = read_object(context, full, self.use_modifiers)
        part_v, part_f, _ = read_object(context, partial, self.use_modifiers)
        options = schema.option_values(self, self.options_schema)
        self._full_name = full.name
        self._partial_name = partial.name
        self._n_original = len(full.data.vertices)
        self._original_to_evaluated = original_to_evaluated
        self._cache_key = cache_key(full)
        self._fingerprint = cache.fingerprint(full_v, full_f, options)
        return LocalizeJob(
            module, full_v, full_f, part_v, part_f, options,
            localizer=cache.CACHE.get(self._cache_key, self._fingerprint),
            on_progress=on_progress,
            time_limit=self.time_limit,
        )

    def _finish(self, context, job):
        if job.localizer is not None and not job.reused:
            cache.CACHE.put(self._cache_key, self._fingerprint, job.localizer)
        stopped = self._stopped(job, "Localization")
        if stopped:
            return stopped
        if job.error is not None:
            exc = job.error
            name = self._full_name if job.phase == "full" else self._partial_name
            self.report({'ERROR'}, f"Localization failed on '{name}': {type(exc).__name__}: {exc}")
            return {'CANCELLED'}
        result = job.result
        full = bpy.data.objects.get(self._full_name)
        if full is None or full.type != 'MESH' or len(full.data.vertices) != self._n_original:
            self.report({'ERROR'}, f"'{self._full_name}' was deleted or edited during the localization; nothing written")
            return {'CANCELLED'}
        region = write_region_on(full, result.region, result.score, self._original_to_evaluated)
        for warning in result.warnings:
            self.report({'WARNING'}, warning)
        prepared = "prepared shape reused" if job.reused else f"shape prepared in {job.localizer.preparation_seconds:.2f} s"
        scale = float(getattr(result, "scale", 1.0))
        if scale != 1.0:
            prepared += f", partial scaled by {scale:.4g}"
        self.report(
            {'INFO'},
            f"Selected {int(region.sum())} of {len(region)} vertices of '{full.name}' "
            f"(confidence {float(result.confidence):.2f}, cost {float(result.cost):.3g}, "
            f"optimised on {int(result.optimisation_vertices)} vertices, {job.elapsed:.1f} s, {prepared})",
        )
        return {'FINISHED'}


#: Custom properties the search sets on each candidate object: its rank (1 = best) and its
#: similarity score (lower is more similar; ``inf`` when the partial could not be located on it).
RANK_PROPERTY = "dualspectra_rank"
SIMILARITY_PROPERTY = "dualspectra_similarity"


def candidate_objects(context):
    """The selected mesh objects other than the active one (the partial), by name."""
    active = context.active_object
    return sorted((ob for ob in context.selected_objects if ob is not active and ob.type == 'MESH'), key=lambda ob: ob.name)


class SearchOperator(JobOperator):
    """Rank the other selected meshes as the shapes the active mesh (a partial shape) may be part of, and select the region on the best"""

    bl_idname = "dualspectra.search"
    bl_label = "Search Selected Objects"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        ob = context.active_object
        if ob is None or ob.type != 'MESH':
            return cls._refuse("The active object must be a mesh (the partial shape)")
        if not candidate_objects(context):
            return cls._refuse("Select the candidate meshes too (the active one is the partial shape)")
        return True

    def draw(self, context):
        layout = self.layout
        for spec in self.options_schema:
            layout.prop(self, spec["name"])
        layout.prop(self, "time_limit")
        layout.prop(self, "use_modifiers")

    def _prepare(self, context, on_progress):
        module = library.load()
        if not hasattr(module, "search"):
            raise UserError(f"dualspectra {getattr(module, '__version__', '?')} has no search; update the add-on's library")
        partial = context.active_object
        if partial is None or partial.type != 'MESH':
            raise UserError("make the partial shape the active object (a mesh)")
        candidates = candidate_objects(context)
        if not candidates:
            raise UserError("select the candidate meshes together with the partial shape (active)")
        part_v, part_f, _ = read_object(context, partial, self.use_modifiers)
        options = schema.option_values(self, self.options_schema)
        self._partial_name = partial.name
        self._candidates = []
        fulls = []
        for ob in candidates:
            v, f, original_to_evaluated = read_object(context, ob, self.use_modifiers)
            key, digest = cache_key(ob), cache.fingerprint(v, f, options)
            self._candidates.append((ob.name, key, digest, original_to_evaluated, len(ob.data.vertices)))
            fulls.append((v, f, cache.CACHE.get(key, digest)))
        return SearchJob(module, part_v, part_f, fulls, options, on_progress=on_progress, time_limit=self.time_limit)

    def _finish(self, context, job):
        for (_, key, digest, _, _), localizer, reused in zip(self._candidates, job.localizers, job.reused):
            if localizer is not None and not reused:
                cache.CACHE.put(key, digest, localizer)
        stopped = self._stopped(job, "Search")
        if stopped:
            return stopped
        if job.error is not None:
            kind, i = job.phase
            name = self._candidates[i][0] if kind == "full" else self._partial_name
            self.report({'ERROR'}, f"Search failed on '{name}': {type(job.error).__name__}: {job.error}")
            return {'CANCELLED'}
        ranking = job.result
        best = ranking[0]
        name, _, _, original_to_evaluated, n_original = self._candidates[best.index]
        full = bpy.data.objects.get(name)
        if full is None or full.type != 'MESH' or len(full.data.vertices) != n_original:
            self.report({'ERROR'}, f"'{name}' was deleted or edited during the search; nothing written")
            return {'CANCELLED'}
        for rank, match in enumerate(ranking, start=1):
            ob = bpy.data.objects.get(self._candidates[match.index][0])
            if ob is not None:
                ob[RANK_PROPERTY] = rank
                ob[SIMILARITY_PROPERTY] = float(match.score)
        found = best.localization
        region = write_region_on(full, found.region, found.score, original_to_evaluated)
        for warning in found.warnings:
            self.report({'WARNING'}, warning)
        for rank, match in enumerate(ranking, start=1):
            candidate = self._candidates[match.index][0]
            if match.localization is None:
                self.report({'INFO'}, f"#{rank} '{candidate}': not located ({match.error})")
            else:
                self.report({'INFO'}, f"#{rank} '{candidate}': score {match.score:.4g} "
                                      f"(confidence {float(match.confidence):.2f})")
        prepared = sum(not r for r in job.reused)
        self.report(
            {'INFO'},
            f"Best match for '{self._partial_name}': '{name}' (score {best.score:.4g}, confidence "
            f"{float(best.confidence):.2f}); selected {int(region.sum())} of {len(region)} vertices; "
            f"{len(ranking)} objects ranked in {job.elapsed:.1f} s ({prepared} prepared, {len(ranking) - prepared} reused)",
        )
        return {'FINISHED'}


def own_properties(with_partial=True):
    """The operator's properties that are not library options (the search has no partial
    object: it is the active one)."""
    props = {
        "partial_object": StringProperty(
            name="Partial",
            description="Mesh object that is a (deformed) part of the active object. "
            "Empty: the panel's choice, else the other selected mesh",
        ),
        "time_limit": FloatProperty(
            name="Time Limit",
            description="Stop with an error after this many seconds (0: no limit)",
            default=0.0, min=0.0, subtype='TIME', unit='TIME_ABSOLUTE',
        ),
        "use_modifiers": BoolProperty(name="Use Modifiers", description="Use the evaluated meshes (modifiers applied)", default=True),
        "background": BoolProperty(
            name="Run in Background",
            description="When started from the interface, compute on a worker thread (Esc cancels)",
            default=True,
            options={'SKIP_SAVE'},
        ),
    }
    if not with_partial:
        del props["partial_object"]
    return props


def option_properties(options_schema):
    """One ``bpy.props`` property per library option (``schema.property_definitions``)."""
    return {name: getattr(bpy.props, kind)(**kwargs) for name, kind, kwargs in schema.property_definitions(options_schema)}


def operator_class(options_schema, base=LocalizeOperator):
    """The operator class (``base``: :class:`LocalizeOperator` or :class:`SearchOperator`)
    with the library's options as properties (Blender reads a class's properties from its
    annotations when it is registered, so the class is made here)."""
    annotations = own_properties(with_partial=base is LocalizeOperator)
    clash = sorted({spec["name"] for spec in options_schema} & set(annotations))
    if clash:
        raise ValueError(f"library options {clash} clash with the operator's own properties")
    annotations.update(option_properties(options_schema))
    name = "DUALSPECTRA_OT_" + base.bl_idname.split(".")[1]
    return type(name, (base, bpy.types.Operator), {
        "__annotations__": annotations,
        "__doc__": base.__doc__,
        "__module__": __name__,
        "options_schema": tuple(options_schema),
    })
