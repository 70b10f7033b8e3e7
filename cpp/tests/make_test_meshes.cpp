// Writes the generated inputs of the example tests into DIR:
//   full.off     a bumpy sphere (icosphere level 4, 2562 vertices)
//   partial.off  its cut {x > -0.25}, moved by a rigid motion plus a small smooth bend
//   truth.txt    the full-mesh vertex index of every partial vertex (the true region)
#include <cmath>
#include <cstdio>
#include <fstream>

#include "test_meshes.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  try {
    const auto full = dstest::bumpy_sphere(4);
    std::vector<std::uint32_t> origin;
    auto part = dstest::cut(full, [](const dstest::Vec3& p) { return p[0] > -0.25; }, &origin);
    // Rotation about z by 0.7 rad, a translation, and a bend z += 0.03 y^2 (non-isometric, small).
    const double c = std::cos(0.7), s = std::sin(0.7);
    for (auto& p : part.V) {
      const dstest::Vec3 q{c * p[0] - s * p[1] + 2.0, s * p[0] + c * p[1] - 1.0, p[2] + 0.03 * p[1] * p[1] + 0.5};
      p = q;
    }
    dstest::write_off(dir + "/full.off", full);
    dstest::write_off(dir + "/partial.off", part);
    std::ofstream t(dir + "/truth.txt");
    for (auto i : origin) t << i << '\n';
    if (!t) throw std::runtime_error("cannot write " + dir + "/truth.txt");
    std::printf("wrote %s/full.off (%zu vertices), partial.off (%zu vertices), truth.txt\n", dir.c_str(), full.V.size(),
                part.V.size());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_test_meshes: %s\n", e.what());
    return 1;
  }
  return 0;
}
