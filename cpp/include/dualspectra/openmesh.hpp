// dualspectra <-> OpenMesh adapter (header-only; link dualspectra::openmesh).
//
//   #include <OpenMesh/Core/IO/MeshIO.hh>
//   #include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
//   #include <dualspectra/openmesh.hpp>
//   OpenMesh::TriMesh_ArrayKernelT<> full_om, part_om;  // float or double points
//   auto full = dualspectra::openmesh::to_mesh(full_om), part = dualspectra::openmesh::to_mesh(part_om);
//   dualspectra::Localization r = dualspectra::localize(full.mesh, part.mesh);  // or a Localizer
//   dualspectra::openmesh::write_region(full_om, full, r);  // bool property + status().selected()
//
// Works with any OpenMesh mesh type (TriMesh or PolyMesh kernels, float or double points).
// Conversion: the non-deleted vertices, in handle order, and the non-deleted faces are the
// host's arrays handed to the core's mesh intake (dualspectra::Mesh::from_host): it leaves out
// zero-area faces and vertices in no face (isolated), splits non-manifold vertices (two sheets
// of faces meeting at one vertex: each extra sheet gets a copy of it), says so in
// conv.mesh.warning() and in the result's warnings, and gives every result back for all
// non-deleted vertices (`false` / 0 at the left-out ones; a split vertex is in the region if
// any copy is). Deleted elements (before garbage_collection) are skipped here. Every face must
// be a triangle: a polygon face throws dualspectra::Error(Status::InvalidMesh) naming it
// (triangulate first: mesh.triangulate()). What the intake cannot use (a non-finite
// coordinate, no faces, every face of zero area) throws Error(Status::InvalidMesh) with its
// reason.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <OpenMesh/Core/Mesh/Handles.hh>
#include <OpenMesh/Core/Utils/Property.hh>

#include "dualspectra/dualspectra.hpp"

namespace dualspectra {
namespace openmesh {

// An OpenMesh mesh converted to a dualspectra::Mesh, with the vertex correspondence.
struct Converted {
  // The non-deleted vertices and faces through the core's intake: per-vertex results have one
  // value per non-deleted vertex (mesh.n_vertices() == vertex_of.size()).
  Mesh mesh;
  // vertex_of[i]: the OpenMesh vertex of host index i (every non-deleted vertex).
  std::vector<OpenMesh::VertexHandle> vertex_of;
  // index_of[vh.idx()]: host index of an OpenMesh vertex, or `none` (deleted).
  std::vector<std::uint32_t> index_of;
  static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();

  std::uint32_t index(OpenMesh::VertexHandle vh) const {
    return vh.is_valid() && static_cast<std::size_t>(vh.idx()) < index_of.size() ? index_of[vh.idx()] : none;
  }
};

// Convert an OpenMesh triangle mesh (throws Error(Status::InvalidMesh) on polygon faces or a
// mesh the intake cannot repair; see the file comment).
template <class OMesh>
Converted to_mesh(const OMesh& om) {
  constexpr std::uint32_t none = Converted::none;
  const std::size_t slots = om.n_vertices();  // handle space, deleted vertices included
  if (slots >= none) throw Error(Status::InvalidMesh, "OpenMesh mesh has too many vertices for 32-bit indices");
  std::vector<std::uint32_t> index_of(slots, none);
  std::vector<OpenMesh::VertexHandle> vertex_of;
  std::vector<double> positions;
  positions.reserve(3 * slots);
  for (auto vh : om.vertices()) {  // skips deleted vertices
    index_of[static_cast<std::size_t>(vh.idx())] = static_cast<std::uint32_t>(vertex_of.size());
    vertex_of.push_back(OpenMesh::VertexHandle(vh.idx()));
    const auto& p = om.point(vh);
    positions.push_back(static_cast<double>(p[0]));
    positions.push_back(static_cast<double>(p[1]));
    positions.push_back(static_cast<double>(p[2]));
  }
  std::vector<std::uint32_t> triangles;
  triangles.reserve(3 * om.n_faces());
  for (auto fh : om.faces()) {  // skips deleted faces
    std::size_t degree = 0;
    for (auto vh : om.fv_range(fh)) {
      if (degree < 3) triangles.push_back(index_of[static_cast<std::size_t>(vh.idx())]);
      ++degree;
    }
    if (degree != 3)
      throw Error(Status::InvalidMesh, "OpenMesh face " + std::to_string(fh.idx()) + " has " + std::to_string(degree) +
                                           " vertices; dualspectra needs a triangle mesh (call mesh.triangulate() first)");
  }
  Mesh mesh = Mesh::from_host(positions, triangles);
  return Converted{std::move(mesh), std::move(vertex_of), std::move(index_of)};
}

// Write per-vertex values of a dualspectra result (one per host index, i.e. per non-deleted
// vertex of om) into the vertex property `name` of om (created if missing, reused if present);
// deleted vertices get `fill`. Throws Error(Status::InvalidArgument) if the sizes do not match.
template <class T, class OMesh, class Values>
OpenMesh::VPropHandleT<T> write_vertex_values(OMesh& om, const Converted& conv, const Values& values,
                                              const std::string& name, T fill) {
  if (values.size() != conv.vertex_of.size())
    throw Error(Status::InvalidArgument, "result has " + std::to_string(values.size()) +
                                             " vertex values but the converted mesh has " +
                                             std::to_string(conv.vertex_of.size()) + " vertices");
  OpenMesh::VPropHandleT<T> h;
  if (!om.get_property_handle(h, name)) om.add_property(h, name);
  for (auto vh : om.all_vertices()) om.property(h, vh) = fill;
  for (std::size_t i = 0; i < conv.vertex_of.size(); ++i) om.property(h, conv.vertex_of[i]) = static_cast<T>(values[i]);
  return h;
}

// The region as a bool vertex property (default "v:dualspectra_region") and, with
// `select = true`, as the vertices' status().selected() flag (vertex status is requested if
// the mesh has none; vertices outside the region are deselected).
template <class OMesh>
OpenMesh::VPropHandleT<bool> write_region(OMesh& om, const Converted& conv, const Localization& result,
                                          const std::string& name = "v:dualspectra_region", bool select = true) {
  auto h = write_vertex_values<bool>(om, conv, result.region, name, false);
  if (select) {
    if (!om.has_vertex_status()) om.request_vertex_status();
    for (auto vh : om.all_vertices()) om.status(vh).set_selected(om.property(h, vh));
  }
  return h;
}

// The soft membership score in [0, 1] as a double vertex property (default "v:dualspectra_score").
template <class OMesh>
OpenMesh::VPropHandleT<double> write_score(OMesh& om, const Converted& conv, const Localization& result,
                                           const std::string& name = "v:dualspectra_score") {
  return write_vertex_values<double>(om, conv, result.score, name, 0.0);
}

}  // namespace openmesh
}  // namespace dualspectra
