// dualspectra <-> CGAL::Surface_mesh adapter (header-only; link dualspectra::cgal).
//
//   #include <dualspectra/cgal.hpp>
//   CGAL::Surface_mesh<K::Point_3> full_sm, part_sm;   // e.g. from CGAL::IO::read_polygon_mesh
//   auto full = dualspectra::cgal::to_mesh(full_sm), part = dualspectra::cgal::to_mesh(part_sm);
//   dualspectra::Localization r = dualspectra::localize(full.mesh, part.mesh);  // or a Localizer
//   auto region = dualspectra::cgal::write_region(full_sm, full, r);  // bool map "v:dualspectra_region"
//   auto score  = dualspectra::cgal::write_score(full_sm, full, r);   // double map "v:dualspectra_score"
//
// Conversion: the live (not removed) vertices, in the order of sm.vertices(), and the faces
// are the host's arrays handed to the core's mesh intake (dualspectra::Mesh::from_host): it
// leaves out zero-area faces and vertices in no face (isolated), splits non-manifold vertices
// (two sheets of faces meeting at one vertex: each extra sheet gets a copy of it), says so in
// conv.mesh.warning() and in the result's warnings, and gives every result back for all live
// vertices (`false` / 0 at the left-out ones; a split vertex is in the region if any copy
// is). Removed elements and non-contiguous indices (a mesh not garbage-collected) are skipped
// here. Coordinates go through CGAL::to_double, so exact kernels work. Every face must be a
// triangle: a polygon face throws dualspectra::Error(Status::InvalidMesh) naming the face
// (triangulate first, e.g. with CGAL::Polygon_mesh_processing::triangulate_faces). What the
// intake cannot use (a non-finite coordinate, no faces, every face of zero area) throws
// Error(Status::InvalidMesh) with its reason.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <CGAL/Surface_mesh.h>
#include <CGAL/number_utils.h>

#include "dualspectra/dualspectra.hpp"

namespace dualspectra {
namespace cgal {

// A Surface_mesh converted to a dualspectra::Mesh, with the vertex correspondence.
template <class Point>
struct Converted {
  using Vertex_index = typename CGAL::Surface_mesh<Point>::Vertex_index;
  // The live vertices and the faces through the core's intake: per-vertex results have one
  // value per live vertex (mesh.n_vertices() == vertex_of.size()).
  Mesh mesh;
  // vertex_of[i]: the Surface_mesh vertex of host index i (every live vertex).
  std::vector<Vertex_index> vertex_of;
  // index_of[v.idx()]: the host index of a Surface_mesh vertex, or `none` (removed).
  std::vector<std::uint32_t> index_of;
  static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();

  // Host index of `v`, or `none`.
  std::uint32_t index(Vertex_index v) const {
    const std::size_t k = static_cast<std::size_t>(v.idx());
    return k < index_of.size() ? index_of[k] : none;
  }
};

namespace detail {
template <class Point>
struct Arrays {
  std::vector<double> positions;
  std::vector<std::uint32_t> triangles;
  std::vector<typename CGAL::Surface_mesh<Point>::Vertex_index> vertex_of;
  std::vector<std::uint32_t> index_of;
};

// The live vertices (host index = rank in sm.vertices()) and the faces in host indices.
template <class Point>
Arrays<Point> arrays(const CGAL::Surface_mesh<Point>& sm) {
  using SM = CGAL::Surface_mesh<Point>;
  using size_type = typename SM::size_type;
  constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
  Arrays<Point> a;
  // Index space, removed elements included (indices are not contiguous before collect_garbage).
  std::size_t slots = 0;
  for (auto v : sm.vertices()) slots = std::max<std::size_t>(slots, static_cast<std::size_t>(v.idx()) + 1);
  a.index_of.assign(slots, none);
  a.positions.reserve(3 * static_cast<std::size_t>(sm.number_of_vertices()));
  for (auto v : sm.vertices()) {
    if (a.vertex_of.size() >= none)
      throw Error(Status::InvalidMesh, "CGAL::Surface_mesh has too many vertices for 32-bit indices");
    a.index_of[static_cast<std::size_t>(v.idx())] = static_cast<std::uint32_t>(a.vertex_of.size());
    a.vertex_of.push_back(v);
    const Point& p = sm.point(v);
    a.positions.push_back(CGAL::to_double(p.x()));
    a.positions.push_back(CGAL::to_double(p.y()));
    a.positions.push_back(CGAL::to_double(p.z()));
  }
  a.triangles.reserve(3 * static_cast<std::size_t>(sm.number_of_faces()));
  for (auto f : sm.faces()) {
    std::size_t degree = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
      if (degree < 3) a.triangles.push_back(a.index_of[static_cast<std::size_t>(v.idx())]);
      ++degree;
    }
    if (degree != 3)
      throw Error(Status::InvalidMesh,
                  "CGAL::Surface_mesh face f" + std::to_string(static_cast<size_type>(f.idx())) + " has " +
                      std::to_string(degree) +
                      " vertices; dualspectra needs a triangle mesh (triangulate first, e.g. "
                      "CGAL::Polygon_mesh_processing::triangulate_faces)");
  }
  return a;
}
}  // namespace detail

// Convert a triangle Surface_mesh (throws Error(Status::InvalidMesh) on polygon faces or a mesh
// the intake cannot repair; see the file comment).
template <class Point>
Converted<Point> to_mesh(const CGAL::Surface_mesh<Point>& sm) {
  auto a = detail::arrays(sm);
  Mesh mesh = Mesh::from_host(a.positions, a.triangles);
  return Converted<Point>{std::move(mesh), std::move(a.vertex_of), std::move(a.index_of)};
}

// Write per-vertex values of a dualspectra result (one per host index, i.e. per live vertex of
// sm) into a vertex property map `name` of sm (created if missing, reused if present). Throws
// Error(Status::InvalidArgument) if the sizes do not match.
template <class Point, class T, class Values>
typename CGAL::Surface_mesh<Point>::template Property_map<typename CGAL::Surface_mesh<Point>::Vertex_index, T>
write_vertex_values(CGAL::Surface_mesh<Point>& sm, const Converted<Point>& conv, const Values& values,
                    const std::string& name, T fill) {
  using V = typename CGAL::Surface_mesh<Point>::Vertex_index;
  if (values.size() != conv.vertex_of.size())
    throw Error(Status::InvalidArgument, "result has " + std::to_string(values.size()) +
                                             " vertex values but the converted mesh has " +
                                             std::to_string(conv.vertex_of.size()) + " vertices");
  auto map = sm.template add_property_map<V, T>(name, fill).first;
  for (std::size_t i = 0; i < conv.vertex_of.size(); ++i) map[conv.vertex_of[i]] = static_cast<T>(values[i]);
  return map;
}

// The region as a bool vertex property map (default name "v:dualspectra_region").
template <class Point>
typename CGAL::Surface_mesh<Point>::template Property_map<typename CGAL::Surface_mesh<Point>::Vertex_index, bool>
write_region(CGAL::Surface_mesh<Point>& sm, const Converted<Point>& conv, const Localization& result,
             const std::string& name = "v:dualspectra_region") {
  return write_vertex_values<Point, bool>(sm, conv, result.region, name, false);
}

// The soft membership score in [0, 1] as a double vertex property map (default "v:dualspectra_score").
template <class Point>
typename CGAL::Surface_mesh<Point>::template Property_map<typename CGAL::Surface_mesh<Point>::Vertex_index, double>
write_score(CGAL::Surface_mesh<Point>& sm, const Converted<Point>& conv, const Localization& result,
            const std::string& name = "v:dualspectra_score") {
  return write_vertex_values<Point, double>(sm, conv, result.score, name, 0.0);
}

}  // namespace cgal
}  // namespace dualspectra
