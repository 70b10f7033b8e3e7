// Reads a region written by an example (--indices: 0-based vertex indices, one a line) and
// reports its size and IoU with a ground truth:
//   check_region REGION N_FULL --truth TRUTH.txt              (0-based indices, one a line)
//   check_region REGION N_FULL --baryc GT [GT_SYM]            (SHREC'16: 1-based triangle of the
//                                     full shape + 3 weights per partial vertex; the truth marks
//                                     the triangle's three vertices; needs --off FULL.off)
// Exit status 1 if the region is empty, the whole mesh, or has an out-of-range index; the IoU is
// reported (a small-budget localization is not required to find the right place).
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "test_meshes.hpp"

static std::vector<char> read_indices(const std::string& path, std::size_t n, bool& ok) {
  std::ifstream is(path);
  if (!is) throw std::runtime_error("cannot read " + path);
  std::vector<char> mask(n, 0);
  long long i = 0;
  while (is >> i) {
    if (i < 0 || static_cast<std::size_t>(i) >= n) ok = false;
    else mask[static_cast<std::size_t>(i)] = 1;
  }
  return mask;
}

static std::vector<char> read_baryc(const std::string& path, const dstest::SimpleMesh& full) {
  std::ifstream is(path);
  if (!is) throw std::runtime_error("cannot read " + path);
  std::vector<char> mask(full.V.size(), 0);
  double t = 0, w1 = 0, w2 = 0, w3 = 0;
  while (is >> t >> w1 >> w2 >> w3) {
    const auto f = static_cast<std::size_t>(t) - 1;
    if (f >= full.F.size()) throw std::runtime_error("triangle out of range in " + path);
    for (auto v : full.F[f]) mask[v] = 1;
  }
  return mask;
}

static double iou(const std::vector<char>& a, const std::vector<char>& b) {
  std::size_t inter = 0, uni = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    inter += a[i] && b[i];
    uni += a[i] || b[i];
  }
  return uni ? static_cast<double>(inter) / static_cast<double>(uni) : 0.0;
}

int main(int argc, char** argv) {
  try {
    if (argc < 3) throw std::runtime_error("usage: check_region REGION N_FULL [--truth F | --off FULL.off --baryc GT [GT_SYM]]");
    const std::size_t n = std::stoul(argv[2]);
    bool ok = true;
    const auto region = read_indices(argv[1], n, ok);
    std::size_t count = 0;
    for (char c : region) count += c;
    std::vector<std::vector<char>> truths;
    dstest::SimpleMesh full;
    for (int i = 3; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--truth" && i + 1 < argc) truths.push_back(read_indices(argv[++i], n, ok));
      else if (a == "--off" && i + 1 < argc) full = dstest::read_off(argv[++i]);
      else if (a == "--baryc") {
        // A host reader may append duplicated vertices to repair a non-manifold file (OpenMesh,
        // CGAL's repairing reader); the file's own vertices keep their numbers.
        if (full.V.empty() || full.V.size() > n) throw std::runtime_error("--baryc needs --off FULL.off first (at most N_FULL vertices)");
        while (i + 1 < argc && argv[i + 1][0] != '-') {
          auto t = read_baryc(argv[++i], full);
          t.resize(n, 0);
          truths.push_back(std::move(t));
        }
      } else throw std::runtime_error("unknown argument " + a);
    }
    std::printf("check_region: %zu of %zu vertices in the region", count, n);
    double best = -1;
    for (const auto& t : truths) best = std::max(best, iou(region, t));
    if (best >= 0) std::printf(", IoU with the ground truth %.3f", best);
    std::printf("\n");
    if (!ok) std::printf("check_region: FAIL index out of range\n");
    if (count == 0 || count == n) std::printf("check_region: FAIL region is %s\n", count == 0 ? "empty" : "the whole mesh");
    return ok && count > 0 && count < n ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "check_region: %s\n", e.what());
    return 1;
  }
}
