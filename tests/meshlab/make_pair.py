"""Generate a full mesh, a part of it cut by a plane, and the known answer (stdlib only).

The full mesh is an icosphere (subdivision level `--level`) made asymmetric by three Gaussian
bumps of different heights and widths, so that exactly one region of it has the spectra of the
part. The part keeps the faces whose three vertices lie on the positive side of a plane, is
re-indexed, then moved by a rigid motion (rotation + translation): it is a part of the full
shape, placed elsewhere. The expected region is the set of full-mesh vertices the part kept.

Outputs in `--out`: full.off, partial.off, expected_region.txt (one full-mesh vertex index per
line); partial2.off and expected_region2.txt, a second part cut by another plane; full_debris.off,
the full mesh with what an editor's mesh may hold and the library's intake leaves out (a loose
vertex, and a zero-area triangle on three more vertices, all after the full mesh's vertices);
points.off (the part's vertices without faces: a point cloud), for an error path;
fin.off, partial.off with a fin (one more triangle, on a new vertex, on an edge inside the
part: three triangles on that edge), which the library's intake splits off, leaving the part
as it was; closed.off (an octahedron: no boundary), which no intake can make a part; and two
other models for a library in which full.off is the one partial.off was cut from:
other_ellipsoid.off (the icosphere stretched to an ellipsoid) and other_bumps.off (the
icosphere with other bumps than full.off's).
"""

import argparse
import math
import os


def icosphere(level):
    t = (1.0 + math.sqrt(5.0)) / 2.0
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
             (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    verts = [normalize(v) for v in verts]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(level):
        midpoint = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoint:
                pa, pb = verts[a], verts[b]
                verts.append(normalize(tuple((pa[i] + pb[i]) / 2 for i in range(3))))
                midpoint[key] = len(verts) - 1
            return midpoint[key]

        new_faces = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new_faces += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new_faces
    return verts, faces


def normalize(v):
    n = math.sqrt(sum(x * x for x in v))
    return tuple(x / n for x in v)


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


# (centre direction, height, width): three distinct bumps make the shape asymmetric.
BUMPS = [((1.0, 0.2, 0.3), 0.45, 0.35), ((-0.3, 1.0, -0.2), 0.25, 0.5), ((0.1, -0.4, -1.0), 0.6, 0.25)]
# The bumps of other_bumps.off: other places, heights and widths.
OTHER_BUMPS = [((-1.0, -0.3, 0.4), 0.6, 0.3), ((0.2, 0.9, 0.6), 0.3, 0.45), ((0.5, -0.6, -0.8), 0.2, 0.6)]
# The cutting planes: keep points p with dot(p, normal) > offset.
PLANE_NORMAL = normalize((1.0, 0.35, 0.25))
PLANE_OFFSET = 0.3
PLANE2_NORMAL = normalize((-0.2, 0.3, -1.0))
PLANE2_OFFSET = 0.25
# Appended to full.off in full_debris.off: a loose vertex and three collinear ones.
DEBRIS = [(5.0, 5.0, 5.0), (4.0, 0.0, 0.0), (4.5, 0.0, 0.0), (5.0, 0.0, 0.0)]


def bumpy(verts, bumps=BUMPS):
    out = []
    for v in verts:
        r = 1.0
        for c, h, w in bumps:
            d2 = sum((x - y) ** 2 for x, y in zip(v, normalize(c)))
            r += h * math.exp(-d2 / (w * w))
        out.append(tuple(r * x for x in v))
    return out


def rigid(p):
    """Rotation by 40 degrees about a skew axis, then a translation."""
    ax = normalize((0.3, -0.5, 0.8))
    th = math.radians(40.0)
    c, s = math.cos(th), math.sin(th)
    cross = (ax[1] * p[2] - ax[2] * p[1], ax[2] * p[0] - ax[0] * p[2], ax[0] * p[1] - ax[1] * p[0])
    d = dot(ax, p)
    rot = tuple(p[i] * c + cross[i] * s + ax[i] * d * (1 - c) for i in range(3))
    return (rot[0] + 3.0, rot[1] - 1.0, rot[2] + 0.5)


def write_off(path, verts, faces):
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(verts), len(faces)))
        for v in verts:
            f.write("%.9g %.9g %.9g\n" % v)
        for t in faces:
            f.write("3 %d %d %d\n" % t)


def write_fin(path, full, region, kept):
    """partial.off (same vertices, same faces, same order) plus a fin: a new last vertex off
    the surface and a last triangle on the first edge of the part whose two faces both hold
    it, inside the part. The edge then has three triangles (non-manifold); the intake glues
    the first two, as they were, and splits the fin off with copies of the edge's ends."""
    new_index = {old: new for new, old in enumerate(region)}
    faces = [tuple(new_index[i] for i in t) for t in kept]
    count = {}
    for t in faces:
        for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            key = (min(e), max(e))
            count[key] = count.get(key, 0) + 1
    a, b = next(e for t in faces for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))
                if count[(min(e), max(e))] == 2)
    verts = [rigid(full[i]) for i in region]
    tip = tuple((verts[a][i] + verts[b][i]) / 2 + (0.2 if i == 2 else 0.0) for i in range(3))
    write_off(path, verts + [tip], faces + [(a, b, len(verts))])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True, help="output directory")
    ap.add_argument("--level", type=int, default=4, help="icosphere subdivision level (4: 2562 vertices)")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)

    sphere, faces = icosphere(args.level)
    full = bumpy(sphere)

    def part(normal, offset, name, truth):
        # The side test uses the unit-sphere positions, so the cut is a clean spherical cap.
        kept = [t for t in faces if all(dot(sphere[i], normal) > offset for i in t)]
        region = sorted({i for t in kept for i in t})
        new_index = {old: new for new, old in enumerate(region)}
        write_off(os.path.join(args.out, name), [rigid(full[i]) for i in region],
                  [tuple(new_index[i] for i in t) for t in kept])
        with open(os.path.join(args.out, truth), "w") as f:
            f.write("".join("%d\n" % i for i in region))
        return region, kept

    region, kept = part(PLANE_NORMAL, PLANE_OFFSET, "partial.off", "expected_region.txt")
    part(PLANE2_NORMAL, PLANE2_OFFSET, "partial2.off", "expected_region2.txt")
    write_off(os.path.join(args.out, "full.off"), full, faces)
    n = len(full)
    write_off(os.path.join(args.out, "full_debris.off"), full + DEBRIS, faces + [(n + 1, n + 2, n + 3)])
    part_points = [rigid(full[i]) for i in region]
    write_off(os.path.join(args.out, "points.off"), part_points, [])
    write_fin(os.path.join(args.out, "fin.off"), full, region, kept)
    write_off(os.path.join(args.out, "other_ellipsoid.off"), [(1.5 * x, 0.9 * y, 0.75 * z) for x, y, z in sphere], faces)
    write_off(os.path.join(args.out, "other_bumps.off"), bumpy(sphere, OTHER_BUMPS), faces)
    write_off(os.path.join(args.out, "closed.off"),
              [(0.3, 0, 0), (-0.3, 0, 0), (0, 0.3, 0), (0, -0.3, 0), (0, 0, 0.3), (0, 0, -0.3)],
              [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)])
    print("full: %d vertices, %d faces; partial: %d vertices, %d faces (%.1f%% of the full vertices)"
          % (len(full), len(faces), len(region), len(kept), 100.0 * len(region) / len(full)))


if __name__ == "__main__":
    main()
