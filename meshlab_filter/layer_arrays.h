// Conversion between a vcg triangle mesh (MeshLab's CMeshO) and the flat arrays of the
// dualspectra C ABI. Independent of MeshLab's plugin interface, so it is unchanged
// between MeshLab 2020.09 (MeshFilterInterface) and 2022+ (FilterPlugin).
//
// Only vcg's deleted elements are handled here. The rest of the cleaning (vertices no face
// uses, zero-area faces) is the core's mesh intake (`ds_mesh_create_from_host`), which keeps
// results in the numbering of these arrays: every per-vertex result of the library has one
// value per packed vertex, mapped back to the layer by `layer_of`.
#ifndef DUALSPECTRA_MESHLAB_LAYER_ARRAYS_H
#define DUALSPECTRA_MESHLAB_LAYER_ARRAYS_H

#include <cstddef>
#include <cstdint>
#include <vector>

#include <vcg/complex/complex.h>

namespace dsml {

/// A mesh layer packed for the C ABI: `xyz` (3 per packed vertex), `tri` (3 per packed face).
/// Deleted vertices and faces are skipped; every other vertex is packed, in layer order, used
/// by a face or not. `packed_of[i]` is the packed index of the layer's vertex `i` (`-1` when
/// deleted); `layer_of[j]` is the layer index of packed vertex `j`.
struct PackedLayer {
    std::vector<double> xyz;
    std::vector<uint32_t> tri;
    std::vector<int64_t> packed_of;
    std::vector<size_t> layer_of;
    size_t n_deleted_vertices = 0;

    size_t n_vertices() const { return layer_of.size(); }
    size_t n_faces() const { return tri.size() / 3; }
};

/// Pack the live vertices and the live faces of `m`.
template <class MeshType>
PackedLayer pack_layer(const MeshType& m)
{
    PackedLayer p;
    const size_t nv = m.vert.size();
    p.packed_of.assign(nv, -1);
    p.xyz.reserve(3 * static_cast<size_t>(m.vn));
    for (size_t i = 0; i < nv; ++i) {
        const auto& v = m.vert[i];
        if (v.IsD()) { ++p.n_deleted_vertices; continue; }
        p.packed_of[i] = static_cast<int64_t>(p.layer_of.size());
        p.layer_of.push_back(i);
        for (int c = 0; c < 3; ++c) p.xyz.push_back(static_cast<double>(v.cP()[c]));
    }
    p.tri.reserve(3 * static_cast<size_t>(m.fn));
    for (const auto& f : m.face) {
        if (f.IsD()) continue;
        // A live face on a deleted vertex (not a valid vcg mesh) becomes an index out of
        // range, which the library reports.
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

/// Write `score[j]` to the quality of the layer vertex of packed vertex `j`. The mesh must
/// have per-vertex quality enabled.
template <class MeshType>
void write_quality(MeshType& m, const PackedLayer& p, const double* score)
{
    using Q = typename MeshType::VertexType::QualityType;
    for (size_t j = 0; j < p.n_vertices(); ++j) m.vert[p.layer_of[j]].Q() = static_cast<Q>(score[j]);
}

/// FNV-1a over the bytes of the packed arrays and their counts: a cheap fingerprint of the
/// layer's geometry (a prepared localizer is reused only for the same fingerprint).
inline uint64_t fingerprint(const PackedLayer& p)
{
    uint64_t h = 1469598103934665603ull;
    auto mix = [&h](const void* data, size_t bytes) {
        const unsigned char* b = static_cast<const unsigned char*>(data);
        for (size_t i = 0; i < bytes; ++i) {
            h ^= b[i];
            h *= 1099511628211ull;
        }
    };
    const uint64_t counts[2] = {p.n_vertices(), p.n_faces()};
    mix(counts, sizeof counts);
    mix(p.xyz.data(), p.xyz.size() * sizeof(double));
    mix(p.tri.data(), p.tri.size() * sizeof(uint32_t));
    return h;
}

} // namespace dsml

#endif
