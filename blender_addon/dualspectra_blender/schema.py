"""The library's options as Blender properties, free of ``bpy``.

``dualspectra.options_schema()`` is the core's table of the localizer's options (name,
label, type, range, default, doc). At registration the operator and the panel settings get
one property per entry, built from :func:`property_definitions` (``bpy`` glue in
``operators.py``), so that an option added to the core appears here with no edit.

Blender limits: an ``IntProperty`` is a signed 32-bit integer, so wider bounds are clamped
to ``2^31 - 1``; a ``FloatProperty`` is single precision, so
:func:`option_values` passes the shortest decimal that stands for the stored value (``0.33``,
not ``0.33000001311302185``). Checks that span options (``resolution`` 0 or at least 200)
stay the library's: it raises, the operator reports.
"""

import numpy as np

INT32_MIN, INT32_MAX = -(2**31), 2**31 - 1


def property_definitions(schema):
    """``[(name, property function name, keyword arguments)]``, one per option of ``schema``.

    ``"IntProperty"``, ``"FloatProperty"`` or ``"EnumProperty"`` with the core's label as
    ``name``, its doc as ``description``, its default and range; enum items are the choice
    names themselves (passed to the library unchanged).
    """
    out = []
    for spec in schema:
        common = {"name": spec["label"], "description": spec["doc"]}
        kind = spec["type"]
        if kind == "int":
            lo, hi = max(INT32_MIN, int(spec["min"])), min(INT32_MAX, int(spec["max"]))
            out.append((spec["name"], "IntProperty", dict(common, default=min(max(int(spec["default"]), lo), hi), min=lo, max=hi)))
        elif kind == "float":
            out.append((spec["name"], "FloatProperty", dict(
                common, default=float(spec["default"]), min=float(spec["min"]), max=float(spec["max"]), precision=3)))
        elif kind == "choice":
            items = tuple((c, c, spec["doc"]) for c in spec["choices"])
            out.append((spec["name"], "EnumProperty", dict(common, items=items, default=spec["default"])))
        else:
            raise ValueError(f"option '{spec['name']}' has a type this add-on does not know: {kind!r}")
    return out


def option_values(source, schema):
    """``{name: value}`` for every option of ``schema``, read as attributes of ``source`` (an
    operator or the panel settings), ready for ``dualspectra.Localizer(**values)``."""
    values = {}
    for spec in schema:
        value = getattr(source, spec["name"])
        if spec["type"] == "float":
            value = float(str(np.float32(value)))
        values[spec["name"]] = value
    return values
