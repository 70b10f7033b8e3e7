"""Find the ``dualspectra`` Python package (with its native ``_dualspectra`` module).

Looked up in this order:

1. beside the add-on: ``<add-on folder>/dualspectra/`` (the package directory unzipped
   from the wheel; how the legacy add-on for Blender < 4.2 is installed);
2. an installed ``dualspectra`` (Blender 4.2+ installs the wheels listed in
   ``blender_manifest.toml`` into the extension's site-packages; a ``bpy`` module in a
   venv sees a ``pip install``-ed wheel).

The import is done once, lazily, so that the add-on registers (and shows an error in
the panel) even when the native module is missing or built for another platform.
"""

import importlib
import importlib.util
import os
import sys

_BESIDE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "dualspectra")

_module = None
_error = None


def _import_beside():
    init = os.path.join(_BESIDE, "__init__.py")
    if not os.path.isfile(init):
        return None
    existing = sys.modules.get("dualspectra")
    if existing is not None:
        # Already imported (e.g. the add-on was disabled and enabled again): a native
        # module cannot be loaded twice into one process, so keep the loaded one.
        return existing
    spec = importlib.util.spec_from_file_location("dualspectra", init, submodule_search_locations=[_BESIDE])
    module = importlib.util.module_from_spec(spec)
    sys.modules["dualspectra"] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules["dualspectra"]
        raise
    return module


def load():
    """The ``dualspectra`` module, or raise ``ImportError`` saying where it was looked for."""
    global _module, _error
    if _module is not None:
        return _module
    if _error is not None:
        raise ImportError(_error)
    try:
        module = _import_beside()
        if module is None:
            module = importlib.import_module("dualspectra")
    except ImportError as exc:
        _error = (
            f"dualspectra native module not found or not loadable ({exc}); looked in {_BESIDE} "
            f"and in Python {sys.version.split()[0]}'s sys.path"
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
