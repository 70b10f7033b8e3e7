// Laws of meshlab_filter/layer_arrays.h on a vcg mesh with deleted and unreferenced vertices
// (no MeshLab needed: vcglib only). Exit status 0 = all checks passed.
//  - packing keeps exactly the live vertices, in layer order, used by a face or not (the
//    library's intake leaves out the unused ones and answers in this numbering);
//  - packed faces are the live faces, with indices mapped through the index map;
//  - a packed mask selects exactly the mapped layer vertices, and the faces whose three
//    vertices are selected; deleted vertices are never selected;
//  - quality: packed scores land on the mapped vertices, deleted ones are untouched;
//  - the fingerprint changes with a coordinate or a face, not with deleted elements.
#include <cstdio>
#include <vector>

#include <vcg/complex/complex.h>
#include <vcg/complex/algorithms/update/selection.h>

#include "layer_arrays.h"

namespace {

class TVertex;
class TFace;
struct TUsedTypes : public vcg::UsedTypes<vcg::Use<TVertex>::AsVertexType, vcg::Use<TFace>::AsFaceType> {};
class TVertex : public vcg::Vertex<TUsedTypes, vcg::vertex::Coord3f, vcg::vertex::Qualityf, vcg::vertex::BitFlags> {};
class TFace : public vcg::Face<TUsedTypes, vcg::face::VertexRef, vcg::face::BitFlags> {};
class TMesh : public vcg::tri::TriMesh<std::vector<TVertex>, std::vector<TFace>> {};

int failures = 0;
void check(bool ok, const char* what)
{
    std::printf("%s %s\n", ok ? "ok  " : "FAIL", what);
    if (!ok) ++failures;
}

} // namespace

int main()
{
    // A 3x3 grid of vertices (0..8), 8 triangles, plus vertex 9 used by no face.
    TMesh m;
    vcg::tri::Allocator<TMesh>::AddVertices(m, 10);
    for (int i = 0; i < 9; ++i) m.vert[i].P() = vcg::Point3f(float(i % 3), float(i / 3), 0.f);
    m.vert[9].P() = vcg::Point3f(5.f, 5.f, 5.f);
    const int tris[8][3] = {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}, {3, 4, 7}, {3, 7, 6}, {4, 5, 8}, {4, 8, 7}};
    for (const auto& t : tris) vcg::tri::Allocator<TMesh>::AddFace(m, &m.vert[t[0]], &m.vert[t[1]], &m.vert[t[2]]);

    // Delete the faces using vertex 2 (faces 2 and 3 use 1,2,5 / 1,5,4: delete face 2 only),
    // then vertex 2, which no live face uses any more.
    vcg::tri::Allocator<TMesh>::DeleteFace(m, m.face[2]);
    vcg::tri::Allocator<TMesh>::DeleteVertex(m, m.vert[2]);

    const dsml::PackedLayer p = dsml::pack_layer(m);
    const std::vector<size_t> expected_layer = {0, 1, 3, 4, 5, 6, 7, 8, 9};
    check(p.layer_of == expected_layer, "packed vertices: the live ones, in layer order (unreferenced 9 included)");
    check(p.n_deleted_vertices == 1, "one deleted vertex counted");
    check(p.packed_of[2] == -1 && p.packed_of[9] == 8, "the deleted vertex maps to -1, the unreferenced one is packed");
    bool inverse = true;
    for (size_t j = 0; j < p.n_vertices(); ++j) inverse = inverse && p.packed_of[p.layer_of[j]] == int64_t(j);
    check(inverse, "packed_of inverts layer_of");
    check(p.n_faces() == 7, "7 live faces packed");
    bool coords = p.xyz.size() == 3 * p.n_vertices();
    for (size_t j = 0; coords && j < p.n_vertices(); ++j)
        for (int c = 0; c < 3; ++c) coords = coords && p.xyz[3 * j + c] == double(m.vert[p.layer_of[j]].P()[c]);
    check(coords, "coordinates copied through the map");
    bool faces = true;
    size_t f_packed = 0;
    for (const auto& f : m.face) {
        if (f.IsD()) continue;
        for (int k = 0; k < 3; ++k)
            faces = faces && p.layer_of[p.tri[3 * f_packed + k]] == size_t(vcg::tri::Index(m, f.cV(k)));
        ++f_packed;
    }
    check(faces && f_packed == p.n_faces(), "face indices map back to the same layer vertices");

    // Select packed vertices of layer vertices {0, 1, 3, 4}: faces (0,1,4) and (0,4,3) are full.
    std::vector<uint8_t> mask(p.n_vertices(), 0);
    for (size_t v : {0u, 1u, 3u, 4u}) mask[size_t(p.packed_of[v])] = 1;
    m.vert[8].SetS(); // a stale selection must be cleared
    const size_t n = dsml::select_region(m, p, mask.data());
    bool sel = n == 4;
    for (size_t i = 0; i < m.vert.size(); ++i) {
        if (m.vert[i].IsD()) continue;
        const bool want = i == 0 || i == 1 || i == 3 || i == 4;
        sel = sel && m.vert[i].IsS() == want;
    }
    check(sel, "mask selects exactly the mapped layer vertices (stale selection cleared)");
    check(m.face[0].IsS() && m.face[1].IsS() && !m.face[3].IsS() && !m.face[4].IsS() &&
              vcg::tri::UpdateSelection<TMesh>::FaceCount(m) == 2,
          "faces with three selected vertices are selected, no others");

    std::vector<double> score(p.n_vertices());
    for (size_t j = 0; j < p.n_vertices(); ++j) score[j] = 0.1 * double(j + 1);
    m.vert[2].Q() = 7.f; // deleted: untouched
    dsml::write_quality(m, p, score.data());
    bool q = m.vert[2].Q() == 7.f;
    for (size_t j = 0; j < p.n_vertices(); ++j) q = q && m.vert[p.layer_of[j]].Q() == float(score[j]);
    check(q, "scores land on the mapped vertices; deleted vertices untouched");

    // Fingerprint: the same for the same live geometry, different after a move or a new face.
    const uint64_t h = dsml::fingerprint(p);
    check(dsml::fingerprint(dsml::pack_layer(m)) == h, "fingerprint: same layer, same value");
    m.vert[2].P() = vcg::Point3f(-1.f, -1.f, -1.f); // deleted vertex moved: not part of the layer
    check(dsml::fingerprint(dsml::pack_layer(m)) == h, "fingerprint: deleted elements do not count");
    m.vert[4].P()[2] += 1e-3f;
    const uint64_t moved = dsml::fingerprint(dsml::pack_layer(m));
    check(moved != h, "fingerprint: a moved vertex changes it");
    vcg::tri::Allocator<TMesh>::AddFace(m, &m.vert[5], &m.vert[8], &m.vert[9]);
    check(dsml::fingerprint(dsml::pack_layer(m)) != moved, "fingerprint: a new face changes it");

    std::printf("%s\n", failures == 0 ? "layer_arrays: all checks passed" : "layer_arrays: FAILED");
    return failures == 0 ? 0 : 1;
}
