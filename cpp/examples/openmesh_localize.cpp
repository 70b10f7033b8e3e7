// Localize a partial shape on a full one with OpenMesh meshes:
//   openmesh_localize FULL PARTIAL OUTPUT [--plane-cuts N --max-iterations N --resolution N ... | --option NAME=VALUE]
// reads both meshes with OpenMesh::IO::read_mesh (OFF, PLY, OBJ, STL, ...) into a TriMesh with
// double points, runs dualspectra::localize, stores the region as the vertex property
// "v:dualspectra_region" and the vertices' `selected` status flag, and writes the full mesh with
// the region as vertex colours (red region, grey elsewhere). Prints the region size, the cost and the confidence.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <dualspectra/openmesh.hpp>

#include "example_options.hpp"

struct DoubleTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

static TriMesh read(const std::string& path) {
  TriMesh m;
  if (!OpenMesh::IO::read_mesh(m, path) || m.n_vertices() == 0)
    throw std::runtime_error("cannot read a mesh from '" + path + "'");
  return m;
}

int main(int argc, char** argv) {
  example::Args args;
  try {
    args = example::parse(argc, argv);
    if (args.help) {
      std::printf("usage: %s%s", argv[0], example::usage_text().c_str());
      return 0;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "openmesh_localize: %s\nusage: %s%s", e.what(), argv[0], example::usage_text().c_str());
    return 2;
  }
  try {
    const auto t0 = std::chrono::steady_clock::now();
    TriMesh full_om = read(args.full);
    const TriMesh part_om = read(args.partial);
    const auto full = dualspectra::openmesh::to_mesh(full_om);
    const auto part = dualspectra::openmesh::to_mesh(part_om);
    std::printf("full: %zu vertices (%zu used), %zu faces; partial: %zu vertices (%zu used), %zu faces\n",
                full.mesh.n_vertices(), full.mesh.used_vertices().size(), full.mesh.n_faces(), part.mesh.n_vertices(),
                part.mesh.used_vertices().size(), part.mesh.n_faces());

    const dualspectra::Localization r =
        dualspectra::localize(full.mesh, part.mesh, args.options, example::progress_printer(args.quiet));
    for (const auto& w : r.warnings) std::printf("warning: %s\n", w.c_str());

    dualspectra::openmesh::write_region(full_om, full, r);  // property + selected flag
    dualspectra::openmesh::write_score(full_om, full, r);
    full_om.request_vertex_colors();
    std::size_t n_region = 0;
    for (auto vh : full_om.vertices()) {
      const bool in = full_om.status(vh).selected();
      full_om.set_color(vh, in ? TriMesh::Color(220, 40, 40) : TriMesh::Color(180, 180, 180));
      n_region += in ? 1 : 0;
    }
    OpenMesh::IO::Options wopt = OpenMesh::IO::Options::VertexColor;
    if (!OpenMesh::IO::write_mesh(full_om, args.output, wopt, 17))
      throw std::runtime_error("cannot write '" + args.output + "'");
    // Indices and the count are OpenMesh's vertex handles: the file's vertex numbers, then the
    // copies OpenMesh's reader appends to repair a non-manifold ("complex") vertex, some of
    // whose originals may be left without faces (SHREC'16 cat: 10,000 in the file, more handles).
    if (!args.indices.empty()) {
      std::ofstream os(args.indices);
      for (auto vh : full_om.vertices())
        if (full_om.status(vh).selected()) os << vh.idx() << '\n';
      if (!os) throw std::runtime_error("cannot write '" + args.indices + "'");
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("region: %zu of %zu vertices\ncost: %.6g\nconfidence: %.2f\nselected start: %zu of %zu\nlocalize: %.2f s, total: %.2f s\nwrote %s\n",
                n_region, static_cast<std::size_t>(full_om.n_vertices()), r.cost, r.confidence, r.selected_start, r.n_starts, r.timings.total, seconds,
                args.output.c_str());
    return 0;
  } catch (const dualspectra::Error& e) {
    std::fprintf(stderr, "openmesh_localize: dualspectra error (status %d): %s\n", static_cast<int>(e.status()), e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "openmesh_localize: %s\n", e.what());
    return 1;
  }
}
