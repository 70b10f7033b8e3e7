"""Find the ``dualspectra`` Python package (with its native ``_dualspectra`` module).

Looked up in this order, by ordinary imports:

1. the add-on's own subpackage ``dualspectra`` (``<add-on>/dualspectra/``, the package
   unzipped from the wheel): how the legacy add-on for Blender < 4.2 is installed
   (``blender_addon/build_extension.py --legacy``); imported relatively, as a vendored module;
2. an installed ``dualspectra``: Blender 4.2+ installs the wheel an extension lists in
   ``blender_manifest.toml`` (the extension has no subpackage of that name); a ``bpy`` module
   in a venv sees a ``pip install``-ed wheel.

The import is done once, lazily, so that the add-on registers (and shows an error in
the panel) even when the native module is missing or built for another platform.
"""

import importlib
import importlib.util
import sys

_module = None
_error = None


def _import():
    """The legacy layout's subpackage if the add-on has one, else the installed package."""
    vendored = f"{__package__}.dualspectra"
    if importlib.util.find_spec(vendored) is not None:
        return importlib.import_module(vendored)
    return importlib.import_module("dualspectra")


def load():
    """The ``dualspectra`` module, or raise ``ImportError`` saying where it was looked for."""
    global _module, _error
    if _module is not None:
        return _module
    if _error is not None:
        raise ImportError(_error)
    try:
        module = _import()
    except ImportError as exc:
        _error = (
            f"dualspectra native module not found or not loadable ({exc}); looked for the add-on's "
            f"subpackage {__package__}.dualspectra and in Python {sys.version.split()[0]}'s sys.path"
        )
        raise ImportError(_error) from exc
    for name in ("Localizer", "options_schema", "Cancelled", "MeshError"):
        if not hasattr(module, name):
            _error = f"the dualspectra module at {getattr(module, '__file__', '?')} has no '{name}'"
            raise ImportError(_error)
    _module = module
    return module


def options_schema():
    """The library's options table (``dualspectra.options_schema()``), or ``[]`` when the
    library cannot be loaded (the add-on still registers; running it reports the error)."""
    try:
        return load().options_schema()
    except ImportError:
        return []


def status():
    """A one-line description for the panel: version and location, or the import error."""
    try:
        module = load()
    except ImportError as exc:
        return False, str(exc)
    return True, f"dualspectra {getattr(module, '__version__', '?')}"
