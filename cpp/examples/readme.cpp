#include <dualspectra/dualspectra.hpp>

#include <cstdio>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s FULL PARTIAL [OTHER_FULL...] (.off, .obj or .ply)\n", argv[0]);
    return 2;
  }
  try {
    // From files; from your arrays (std::vector<double> xyz, std::vector<std::uint32_t>
    // triangles): dualspectra::Mesh full(V, F), or Mesh::from_host(V, F) to repair them.
    dualspectra::Mesh full = dualspectra::Mesh::read(argv[1]);
    dualspectra::Mesh part = dualspectra::Mesh::read(argv[2]);
    if (!part.warning().empty()) std::fprintf(stderr, "warning: %s\n", part.warning().c_str());

    // Lighter than the defaults, so that this example runs in seconds.
    dualspectra::Options options;
    options.set("k", 8).set("max_iterations", 10);
    dualspectra::Localizer localizer(full, options);           // prepare the full shape once,
    dualspectra::Localization found = localizer.locate(part);  // then locate any partial on it
    // found.region: one flag per vertex of full; found.confidence, in [0, 1]: the estimated
    // probability that the partial is part of full and IoU >= 0.5, reject low ones. In one call: dualspectra::localize(full, part, options)
    std::printf("region: %zu of %zu vertices, confidence %.2f\n", found.region_vertices().size(),
                full.n_vertices(), found.confidence);

    localizer.save("full.dsprep");  // Localizer::load("full.dsprep") later: no preparation
    // Which model is the part from? Every full shape prepared once, then ranked, best first.
    std::vector<dualspectra::Localizer> library;
    library.push_back(dualspectra::Localizer::load("full.dsprep"));
    for (int i = 3; i < argc; ++i) library.emplace_back(dualspectra::Mesh::read(argv[i]), options);
    std::vector<dualspectra::Match> ranked = dualspectra::search(part, library);  // .localization too
    std::printf("best match: %s (score %.3g)\n", ranked[0].index == 0 ? argv[1] : argv[ranked[0].index + 2],
                ranked[0].score);
  } catch (const dualspectra::Error& e) {  // e.status(): Status::Io, Status::InvalidMesh, ...
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
