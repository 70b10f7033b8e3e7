// Localize a partial shape on a full one with CGAL meshes:
//   cgal_localize FULL PARTIAL OUTPUT [--plane-cuts N --max-iterations N --resolution N ... | --option NAME=VALUE]
// reads both meshes with CGAL::IO::read_polygon_mesh (OFF, PLY, OBJ, STL, ...), runs
// dualspectra::localize, stores the result in the full mesh's vertex property maps
// "v:dualspectra_region" (bool) and "v:dualspectra_score" (double), and writes the full mesh
// with the region as vertex colours (red region, grey elsewhere; a .ply output also carries the
// score as a "dualspectra_score" vertex property). Prints the region size, the cost and the confidence.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/Color.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Polygon_mesh_processing/IO/polygon_mesh_io.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>

#include <dualspectra/cgal.hpp>

#include "example_options.hpp"

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;

// CGAL's plain reader first (vertices keep the file's numbering); if the file is not a valid
// oriented 2-manifold polygon mesh (e.g. SHREC'16 null/cat.off, whose two-sided flaps make
// non-manifold edges), CGAL's repairing reader (polygon soup repair + orientation, which may
// duplicate vertices at non-manifold places: they are appended after the file's vertices).
static SurfaceMesh read(const std::string& path) {
  SurfaceMesh sm;
  if (CGAL::IO::read_polygon_mesh(path, sm) && !sm.is_empty()) return sm;
  sm.clear();
  if (!CGAL::Polygon_mesh_processing::IO::read_polygon_mesh(path, sm, CGAL::parameters::verbose(false)) || sm.is_empty())
    throw std::runtime_error("cannot read a polygon mesh from '" + path + "'");
  std::printf("note: '%s' is not a valid polygon mesh as written; repaired by "
              "CGAL::Polygon_mesh_processing::IO::read_polygon_mesh (%zu vertices)\n",
              path.c_str(), static_cast<std::size_t>(sm.number_of_vertices()));
  return sm;
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
    std::fprintf(stderr, "cgal_localize: %s\nusage: %s%s", e.what(), argv[0], example::usage_text().c_str());
    return 2;
  }
  try {
    const auto t0 = std::chrono::steady_clock::now();
    SurfaceMesh full_sm = read(args.full);
    const SurfaceMesh part_sm = read(args.partial);
    const auto full = dualspectra::cgal::to_mesh(full_sm);
    const auto part = dualspectra::cgal::to_mesh(part_sm);
    std::printf("full: %zu vertices (%zu used), %zu faces; partial: %zu vertices (%zu used), %zu faces\n",
                full.mesh.n_vertices(), full.mesh.used_vertices().size(), full.mesh.n_faces(), part.mesh.n_vertices(),
                part.mesh.used_vertices().size(), part.mesh.n_faces());

    const dualspectra::Localization r =
        dualspectra::localize(full.mesh, part.mesh, args.options, example::progress_printer(args.quiet));
    for (const auto& w : r.warnings) std::printf("warning: %s\n", w.c_str());

    auto region = dualspectra::cgal::write_region(full_sm, full, r);
    dualspectra::cgal::write_score(full_sm, full, r);
    auto colour = full_sm.add_property_map<SurfaceMesh::Vertex_index, CGAL::IO::Color>("v:color").first;
    std::size_t n_region = 0;
    for (auto v : full_sm.vertices()) {
      colour[v] = region[v] ? CGAL::IO::Color(220, 40, 40) : CGAL::IO::Color(180, 180, 180);
      n_region += region[v] ? 1 : 0;
    }
    bool ok = false;
    if (example::ends_with(args.output, ".ply")) {
      std::ofstream os(args.output);
      CGAL::IO::set_ascii_mode(os);
      os.precision(17);  // lossless doubles
      ok = CGAL::IO::write_PLY(os, full_sm) && static_cast<bool>(os);  // writes v:color and the double score map
    } else {
      ok = CGAL::IO::write_polygon_mesh(args.output, full_sm,
                                        CGAL::parameters::vertex_color_map(colour).stream_precision(17));
    }
    if (!ok) throw std::runtime_error("cannot write '" + args.output + "'");
    if (!args.indices.empty()) {
      std::ofstream os(args.indices);
      for (auto v : full_sm.vertices())
        if (region[v]) os << static_cast<std::size_t>(v.idx()) << '\n';
      if (!os) throw std::runtime_error("cannot write '" + args.indices + "'");
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("region: %zu of %zu vertices\ncost: %.6g\nconfidence: %.2f\nselected start: %zu of %zu\nlocalize: %.2f s, total: %.2f s\nwrote %s\n",
                n_region, full.mesh.n_vertices(), r.cost, r.confidence, r.selected_start, r.n_starts, r.timings.total, seconds,
                args.output.c_str());
    return 0;
  } catch (const dualspectra::Error& e) {
    std::fprintf(stderr, "cgal_localize: dualspectra error (status %d): %s\n", static_cast<int>(e.status()), e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cgal_localize: %s\n", e.what());
    return 1;
  }
}
