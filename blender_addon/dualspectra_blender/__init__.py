"""dualspectra for Blender: find the region of a mesh that a partial mesh is.

Partial shape localization by multi-metric Hamiltonian spectra matching (the
``dualspectra`` library). 3D View > Sidebar > DualSpectra. Works as a legacy add-on
(Blender 3.4+, the ``dualspectra`` package unzipped beside this file) and as an
extension (Blender 4.2+, ``blender_manifest.toml`` with the wheel under ``wheels/``).
"""

bl_info = {
    "name": "DualSpectra: Partial Shape Localization",
    "author": "dualspectra contributors",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > DualSpectra",
    "description": "Select the region of the active mesh that another (partial, deformed) mesh corresponds to",
    "category": "Mesh",
}

if "bpy" in locals():
    import importlib

    for _name in ("mesh_data", "job", "library", "operators", "panel"):
        if _name in locals():
            importlib.reload(locals()[_name])

import bpy

from . import job, library, mesh_data, operators, panel

classes = operators.classes + panel.classes


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.dualspectra = bpy.props.PointerProperty(type=panel.DualSpectraSettings)


def unregister():
    del bpy.types.Scene.dualspectra
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
