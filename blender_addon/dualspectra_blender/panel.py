"""The sidebar panel (3D View > Sidebar > DualSpectra) and its scene settings."""

import bpy
from bpy.props import EnumProperty, IntProperty, PointerProperty

from . import library
from .operators import MODES, DUALSPECTRA_OT_localize, default_partial


def _is_mesh(_settings, ob):
    return ob.type == 'MESH'


class DualSpectraSettings(bpy.types.PropertyGroup):
    """Per-scene choices shown in the panel and passed to the operator."""

    partial: PointerProperty(
        name="Partial",
        type=bpy.types.Object,
        poll=_is_mesh,
        description="Mesh object that is a (deformed) part of the active object. Empty: the other selected mesh",
    )
    mode: EnumProperty(name="Mode", items=MODES, default='DUAL')
    k: IntProperty(name="k", description="Eigenvalues per spectrum", default=20, min=1, max=200, soft_max=60)


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
        col.prop(settings, "mode")
        col.prop(settings, "k")

        row = layout.row()
        row.scale_y = 1.4
        op = row.operator(DUALSPECTRA_OT_localize.bl_idname, icon='VIEWZOOM')
        op.partial_object = settings.partial.name if settings.partial is not None else ""
        op.mode = settings.mode
        op.k = settings.k


classes = (DualSpectraSettings, VIEW3D_PT_dualspectra)
