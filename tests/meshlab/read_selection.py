"""Read the vertex selection of a PLY saved by meshlabserver with `-m vf sa`.

meshlabserver writes the vcg vertex flags as a per-vertex `flags` property; a selected vertex
has bit 0x20 set (vcg::VertexBase SELECTED). Deleted vertices are not written, so vertex `i`
of the file is vertex `i` of the input when the input had none (our generated meshes).
"""

import sys

SELECTED = 0x20


def read_selected(path):
    """Return (number of vertices, sorted list of selected vertex indices)."""
    with open(path, "rb") as f:
        data = f.read().decode("ascii", errors="replace")
    lines = iter(data.splitlines())
    if next(lines).strip() != "ply":
        raise ValueError("%s: not a PLY file" % path)
    n_vertices = None
    vertex_props = []
    element = None
    for line in lines:
        words = line.split()
        if not words:
            continue
        if words[0] == "format" and words[1] != "ascii":
            raise ValueError("%s: expected an ascii PLY (meshlabserver -m ... sa)" % path)
        if words[0] == "element":
            element = words[1]
            if element == "vertex":
                n_vertices = int(words[2])
        elif words[0] == "property" and element == "vertex":
            if words[1] == "list":
                raise ValueError("%s: unexpected list property on vertices" % path)
            vertex_props.append(words[-1])
        elif words[0] == "end_header":
            break
    if n_vertices is None or "flags" not in vertex_props:
        raise ValueError("%s: no per-vertex flags (save with -m vf)" % path)
    col = vertex_props.index("flags")
    selected = []
    for i in range(n_vertices):
        fields = next(lines).split()
        if int(float(fields[col])) & SELECTED:
            selected.append(i)
    return n_vertices, selected


if __name__ == "__main__":
    n, sel = read_selected(sys.argv[1])
    print("%d vertices, %d selected" % (n, len(sel)))
