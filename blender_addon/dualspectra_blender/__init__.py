"""dualspectra for Blender: find the region of a mesh that a partial mesh is, and which of
several meshes a partial mesh is part of.

Partial shape localization by multi-metric Hamiltonian spectra matching (the
``dualspectra`` library). 3D View > Sidebar > DualSpectra: *Localize Partial Shape* and
*Search Selected Objects* (``operators.py``). Works as a legacy add-on
(Blender 3.4+, the ``dualspectra`` package unzipped beside this file) and as an
extension (Blender 4.2+, ``blender_manifest.toml`` with the wheel under ``wheels/``).

The operator's and the panel's option properties are made at registration from the
library's options table, so they are the library's (when the library cannot be loaded the
add-on registers without them and reports the import error). The library's warnings
(``dualspectra.DualspectraWarning``) for the add-on's own calls are not printed: the
operator reports them.
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

    for _name in ("mesh_data", "schema", "cache", "job", "library", "operators", "panel"):
        if _name in locals():
            importlib.reload(locals()[_name])

import re
import warnings

import bpy

from . import cache, job, library, mesh_data, operators, panel, schema

classes = ()
_warning_filter = None


def _quiet_library_warnings():
    """Ignore the library's warnings raised for the job module's calls (only those: other
    scripts using ``dualspectra`` keep theirs); returns the filter entry, or ``None``."""
    try:
        category = library.load().DualspectraWarning
    except (ImportError, AttributeError):
        return None
    warnings.filterwarnings("ignore", category=category, module=re.escape(job.__name__) + "$")
    return warnings.filters[0]


def register():
    global classes, _warning_filter
    options_schema = library.options_schema()
    settings = panel.settings_class(options_schema)
    classes = (
        operators.operator_class(options_schema),
        operators.operator_class(options_schema, base=operators.SearchOperator),
        settings,
        panel.VIEW3D_PT_dualspectra,
    )
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.dualspectra = bpy.props.PointerProperty(type=settings)
    bpy.app.handlers.load_pre.append(operators.clear_cache)
    _warning_filter = _quiet_library_warnings()


def unregister():
    global classes, _warning_filter
    if _warning_filter in warnings.filters:
        warnings.filters.remove(_warning_filter)
    _warning_filter = None
    if operators.clear_cache in bpy.app.handlers.load_pre:
        bpy.app.handlers.load_pre.remove(operators.clear_cache)
    cache.CACHE.clear()
    del bpy.types.Scene.dualspectra
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
    classes = ()
