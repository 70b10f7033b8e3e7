// dualspectra::search and Localizer::save/load through the C++ API, on a small generated
// library: the bumpy sphere a part was cut from (then moved) ranks first among it, an ellipsoid
// and a spindle; the best match is what Localizer::locate finds, its score the Localization's
// similarity_score; a saved localizer loads back and locates and searches as the saved one
// did; foreign and stale files throw Status::InvalidPreparedShape, bad arguments
// InvalidArgument, and the progress callback cancels.
#include <cmath>
#include <dualspectra/dualspectra.hpp>

#include <cstdio>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "test_meshes.hpp"

namespace {

using dstest::SimpleMesh;

dualspectra::Mesh to_mesh(const SimpleMesh& m) { return dualspectra::Mesh(m.V, m.F); }

SimpleMesh scaled(SimpleMesh m, double sx, double sy, double sz) {
  for (auto& v : m.V) v = {sx * v[0], sy * v[1], sz * v[2]};
  return m;
}

// The icosphere with radius 1 + 0.6 z^2: a spindle.
SimpleMesh spindle(int level) {
  SimpleMesh m = dstest::icosphere(level);
  for (auto& v : m.V) {
    const double r = 1.0 + 0.6 * v[2] * v[2];
    for (auto& c : v) c *= r;
  }
  return m;
}

// Status of the dualspectra::Error `f` throws (Status::Ok if it throws none), its message in `what`.
template <class F>
dualspectra::Status status_of(F&& f, std::string& what) {
  try {
    f();
  } catch (const dualspectra::Error& e) {
    what = e.what();
    return e.status();
  }
  what.clear();
  return dualspectra::Status::Ok;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string temp_path(const std::string& name) {
  const char* dir = std::getenv("TMPDIR");
  return std::string(dir && *dir ? dir : "/tmp") + "/dualspectra_test_search_" + name;
}

}  // namespace

int main() {
  dstest::Checker t;
  const int right = 1;
  const SimpleMesh full = dstest::bumpy_sphere(3);
  std::vector<std::uint32_t> origin;
  SimpleMesh part = dstest::cut(full, [](const dstest::Vec3& p) { return p[0] > 0.15; }, &origin);
  for (auto& v : part.V) v = {v[0] + 3.0, v[1] - 1.0, v[2] + 0.5};
  const dualspectra::Mesh partial = to_mesh(part);

  dualspectra::Options options;
  options.set("k", 6).set("max_iterations", 10).set("threads", 2);
  std::vector<dualspectra::Localizer> library;
  for (const SimpleMesh& m : {scaled(dstest::icosphere(3), 1.6, 1.0, 0.7), full, spindle(3)})
    library.emplace_back(to_mesh(m), options);

  // The ranking: the model the part was cut from first, best (lowest score) first.
  std::vector<double> fractions;
  const auto ranked = dualspectra::search(partial, library, 10, [&](double f, std::string_view) {
    fractions.push_back(f);
    return true;
  });
  std::string order;
  for (const auto& m : ranked) order += " " + std::to_string(m.index) + ":" + std::to_string(m.score);
  t.check(ranked.size() == library.size(), "every shape is ranked (top above the count)");
  t.check(!ranked.empty() && ranked[0].index == right, "the bumpy sphere the part was cut from ranks first:" + order);
  bool sorted = true, scored = true;
  for (std::size_t i = 0; i < ranked.size(); ++i) {
    if (i > 0 && ranked[i - 1].score > ranked[i].score) sorted = false;
    const auto& m = ranked[i];
    if (!m.located || !m.error.empty() || m.score != m.localization.similarity_score ||
        m.localization.region.size() != library[m.index].n_vertices())
      scored = false;
  }
  t.check(sorted, "scores ascend");
  t.check(scored, "each match is located, its score its Localization's similarity_score, its region that shape's");
  t.check(!fractions.empty() && fractions.back() == 1.0, "progress runs to 1");

  // The best match's region overlaps the cut.
  const auto& best = ranked[0].localization;
  std::size_t both = 0, either = 0;
  std::vector<bool> truth(full.V.size(), false);
  for (std::uint32_t v : origin) truth[v] = true;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    both += truth[i] && best.region[i];
    either += truth[i] || best.region[i];
  }
  std::printf("best match IoU %.3f, confidence %.2f\n", double(both) / double(either), best.confidence);
  t.check(5 * both >= 2 * either, "its region overlaps the cut with IoU >= 0.4");

  // Save and load: locate gives the best match's answer, and the loaded shape searches as the
  // saved one did.
  const std::string saved = temp_path("full.dsprep");
  library[right].save(saved);
  const dualspectra::Localizer loaded = dualspectra::Localizer::load(saved);
  t.check(loaded.n_vertices() == library[right].n_vertices() && loaded.options().json() == options.json(),
          "the loaded localizer has the shape's vertices and options");
  const auto again = loaded.locate(partial);
  t.check(again.region == best.region && again.similarity_score == best.similarity_score,
          "Localizer::locate on the loaded shape gives the best match (region and score)");
  const auto alone = dualspectra::search(partial, std::vector<const dualspectra::Localizer*>{&loaded}, 1);
  t.check(alone.size() == 1 && alone[0].index == 0 && alone[0].score == ranked[0].score,
          "the loaded shape searched alone: the same score");

  // Foreign, stale and missing files, bad arguments, cancel: the error's status and message.
  auto expect = [&](const std::function<void()>& f, dualspectra::Status wanted, const std::string& says,
                    const std::string& label) {
    std::string what;
    const dualspectra::Status got = status_of(f, what);
    t.check(got == wanted && contains(what, says), label + " (" + what + ")");
  };
  std::string bytes;
  {
    std::ifstream in(saved, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const std::string stale = temp_path("stale.dsprep"), foreign = temp_path("foreign.dsprep");
  {
    std::string changed = bytes;
    if (changed.size() > 12) changed[8] = static_cast<char>(changed[8] + 1);  // the format version, after the magic
    std::ofstream(stale, std::ios::binary) << changed;
    std::ofstream(foreign, std::ios::binary) << "OFF\n3 1 0\n";
  }
  auto load = [](const std::string& path) { return [path] { dualspectra::Localizer::load(path); }; };
  expect(load(stale), dualspectra::Status::InvalidPreparedShape, stale + ": stale prepared shape",
         "a stale file: InvalidPreparedShape naming it");
  expect(load(foreign), dualspectra::Status::InvalidPreparedShape, "not a dualspectra prepared shape",
         "a foreign file: InvalidPreparedShape");
  expect(load(temp_path("missing.dsprep")), dualspectra::Status::Io, "missing.dsprep", "a missing file: Io");
  std::remove(saved.c_str());
  std::remove(stale.c_str());
  std::remove(foreign.c_str());

  // A screened search with a shortlist of 1 locates the part on the shape the screen ranks
  // best only; the others follow not located, without an error, with their screen score.
  const auto screened = dualspectra::search(partial, library, 10, {}, 1);
  t.check(screened.size() == library.size() && screened[0].index == right && screened[0].located &&
              screened[0].localization.region == best.region,
          "shortlist 1: the shape the part was cut from, located as by the full search");
  bool rest = true;
  for (std::size_t i = 1; i < screened.size(); ++i)
    rest = rest && !screened[i].located && screened[i].error.empty() &&
           screened[i].screen_score >= screened[0].screen_score;
  t.check(rest, "shortlist 1: the others screened out, with a screen score no better than the first's");
  t.check(std::isnan(ranked[0].screen_score), "an unscreened search has no screen score");
  t.check(!screened[0].quick, "shortlist 1: localized in full");
  // A shortlist of 3 of 4 shapes (the part's own shape twice) is localized quickly, and the
  // best of those again in full with its twin (tied, so within 4 %), ranked first.
  const std::vector<const dualspectra::Localizer*> four{&library[0], &library[1], &library[2], &library[1]};
  const auto two_stage = dualspectra::search(partial, four, 10, {}, 3);
  std::size_t in_full = 0, quick = 0;
  bool full_first = true;
  for (const auto& m : two_stage) {
    if (!m.located) continue;
    if (m.quick) ++quick; else { ++in_full; full_first = full_first && quick == 0; }
  }
  t.check(two_stage.size() == 4 && in_full == 2 && quick == 1 && full_first && two_stage[0].localization.region == best.region,
          "shortlist 3 of 4: one quick localization, the best two in full and first");
  bool confidences = true;
  for (const auto& m : two_stage)
    confidences = confidences && (m.located ? (m.confidence >= 0.0 && m.confidence <= 1.0) : m.confidence == 0.0);
  t.check(confidences, "the search's confidence: in [0, 1] when located, 0 when screened out");
  expect([&] { dualspectra::search(partial, library, 10, {}, 0); }, dualspectra::Status::InvalidArgument,
         "shortlist is 0", "shortlist = 0: InvalidArgument");

  const std::vector<const dualspectra::Localizer*> with_null{&library[0], nullptr};
  expect([&] { dualspectra::search(partial, with_null); }, dualspectra::Status::InvalidArgument,
         "localizers[1] is null", "a null localizer: InvalidArgument");
  expect([&] { dualspectra::search(partial, library, 0); }, dualspectra::Status::InvalidArgument, "top is 0",
         "top = 0: InvalidArgument");
  t.check(dualspectra::search(partial, std::vector<dualspectra::Localizer>{}).empty(), "no shapes: no matches");
  expect([&] { dualspectra::search(partial, library, 1, [](double, std::string_view) { return false; }); },
         dualspectra::Status::Cancelled, "cancelled", "the callback cancels");

  std::printf("%s\n", t.failures ? "FAILED" : "all checks passed");
  return t.failures ? 1 : 0;
}
