// Conversion between a vcg triangle mesh (MeshLab's CMeshO) and the flat arrays of the
// dualspectra C ABI. Independent of MeshLab's plugin interface, so it is unchanged
// between MeshLab 2020.09 (MeshFilterInterface) and 2022+ (FilterPlugin).
#ifndef DUALSPECTRA_MESHLAB_LAYER_ARRAYS_H
#define DUALSPECTRA_MESHLAB_LAYER_ARRAYS_H

#include <cstddef>
#include <cstdint>
#include <vector>

#include <vcg/complex/complex.h>

namespace dsml {

/// A mesh layer packed for the C ABI: `xyz` (3 per packed vertex), `tri` (3 per packed face).
/// Deleted vertices and faces are skipped, and so are vertices that no live face uses
/// (the core rejects isolated vertices). `packed_of[i]` is the packed index of the layer's
/// vertex `i` (`-1` when skipped); `layer_of[j]` is the layer index of packed vertex `j`.
struct PackedLayer {
    std::vector<double> xyz;
    std::vector<uint32_t> tri;
    std::vector<int64_t> packed_of;
    std::vector<size_t> layer_of;
    size_t n_deleted_vertices = 0;
    size_t n_unreferenced_vertices = 0;

    size_t n_vertices() const { return layer_of.size(); }
    size_t n_faces() const { return tri.size() / 3; }
};

/// Pack the live, referenced vertices and the live faces of `m`.
template <class MeshType>
PackedLayer pack_layer(const MeshType& m)
{
    PackedLayer p;
    const size_t nv = m.vert.size();
    p.packed_of.assign(nv, -1);
    std::vector<char> used(nv, 0);
    for (const auto& f : m.face) {
        if (f.IsD()) continue;
        for (int j = 0; j < 3; ++j) used[vcg::tri::Index(m, f.cV(j))] = 1;
    }
    for (size_t i = 0; i < nv; ++i) {
        const auto& v = m.vert[i];
        if (v.IsD()) { ++p.n_deleted_vertices; continue; }
        if (!used[i]) { ++p.n_unreferenced_vertices; continue; }
        p.packed_of[i] = static_cast<int64_t>(p.layer_of.size());
        p.layer_of.push_back(i);
        for (int c = 0; c < 3; ++c) p.xyz.push_back(static_cast<double>(v.cP()[c]));
    }
    p.tri.reserve(3 * static_cast<size_t>(m.fn));
    for (const auto& f : m.face) {
        if (f.IsD()) continue;
        for (int j = 0; j < 3; ++j)
            p.tri.push_back(static_cast<uint32_t>(p.packed_of[vcg::tri::Index(m, f.cV(j))]));
    }
    return p;
}

/// Select the layer vertices whose packed index has `mask[j] != 0` (the previous vertex and
/// face selections are cleared), then the faces whose three vertices are all selected.
/// Returns the number of selected vertices.
template <class MeshType>
size_t select_region(MeshType& m, const PackedLayer& p, const uint8_t* mask)
{
    vcg::tri::UpdateSelection<MeshType>::VertexClear(m);
    vcg::tri::UpdateSelection<MeshType>::FaceClear(m);
    size_t n = 0;
    for (size_t j = 0; j < p.n_vertices(); ++j) {
        if (mask[j]) {
            m.vert[p.layer_of[j]].SetS();
            ++n;
        }
    }
    vcg::tri::UpdateSelection<MeshType>::FaceFromVertexStrict(m);
    return n;
}

/// Write `score[j]` to the quality of the layer vertex of packed vertex `j`; skipped
/// vertices get quality 0. The mesh must have per-vertex quality enabled.
template <class MeshType>
void write_quality(MeshType& m, const PackedLayer& p, const double* score)
{
    using Q = typename MeshType::VertexType::QualityType;
    for (auto& v : m.vert)
        if (!v.IsD()) v.Q() = Q(0);
    for (size_t j = 0; j < p.n_vertices(); ++j) m.vert[p.layer_of[j]].Q() = static_cast<Q>(score[j]);
}

} // namespace dsml

#endif
