"""The sidebar panel (3D View > Sidebar > DualSpectra) and its scene settings.

The settings hold the partial object and one property per library option, made from the
same table as the operators' (:func:`settings_class`); both buttons (*Localize Partial
Shape*, *Search Selected Objects*) pass the options on.
"""

import bpy
from bpy.props import PointerProperty

from . import library
from .operators import LocalizeOperator, SearchOperator, candidate_objects, default_partial, option_properties


def _is_mesh(_settings, ob):
    return ob.type == 'MESH'


def settings_class(options_schema):
    """The per-scene settings group with the library's options as properties."""
    annotations = {
        "partial": PointerProperty(
            name="Partial",
            type=bpy.types.Object,
            poll=_is_mesh,
            description="Mesh object that is a (deformed) part of the active object. Empty: the other selected mesh",
        ),
    }
    annotations.update(option_properties(options_schema))
    return type("DualSpectraSettings", (bpy.types.PropertyGroup,), {
        "__annotations__": annotations,
        "__doc__": "Per-scene choices shown in the panel and passed to the operator.",
        "__module__": __name__,
        "options_schema": tuple(options_schema),
    })


class VIEW3D_PT_dualspectra(bpy.types.Panel):
    bl_label = "Partial Shape Localization"
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "DualSpectra"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.dualspectra
        ok, message = library.status()
        if not ok:
            box = layout.box()
            box.label(text="Native module missing", icon='ERROR')
            box.label(text=message[:120])

        active = context.active_object
        col = layout.column()
        col.label(text=f"Full: {active.name}" if active is not None and active.type == 'MESH' else "Full: (make a mesh active)",
                  icon='MESH_DATA')
        col.prop(settings, "partial")
        if settings.partial is None:
            other = default_partial(context)
            col.label(text=f"Using selected: {other.name}" if other is not None else "Select one other mesh, or pick it above",
                      icon='INFO')
        names = [spec["name"] for spec in settings.options_schema]
        for name in names:
            col.prop(settings, name)

        row = layout.row()
        row.scale_y = 1.4
        op = row.operator(LocalizeOperator.bl_idname, icon='VIEWZOOM')
        op.partial_object = settings.partial.name if settings.partial is not None else ""
        for name in names:
            setattr(op, name, getattr(settings, name))

        # Search: the active mesh is the partial, the other selected meshes the candidates.
        layout.separator()
        col = layout.column()
        n = len(candidate_objects(context)) if active is not None and active.type == 'MESH' else 0
        col.label(text=f"Search: is '{active.name}' part of one of {n} selected meshes?" if n else
                  "Search: select the candidates, then the partial (active)", icon='INFO')
        row = layout.row()
        row.scale_y = 1.4
        row.enabled = n > 0
        op = row.operator(SearchOperator.bl_idname, icon='ZOOM_SELECTED')
        for name in names:
            setattr(op, name, getattr(settings, name))
