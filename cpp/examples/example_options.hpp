// Command-line options shared by the CGAL and OpenMesh examples.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <dualspectra/dualspectra.hpp>

namespace example {

struct Args {
  std::string full, partial, output, indices;
  dualspectra::Options options = dualspectra::default_options();
  bool quiet = false;
};

inline const char* usage_text() {
  return "  FULL PARTIAL OUTPUT [options]\n"
         "  FULL, PARTIAL: triangle meshes (OFF, PLY, OBJ, ...) read by the host library\n"
         "  OUTPUT: the full mesh with the region as vertex colours (red = region) and the score\n"
         "options (defaults: the paper's settings):\n"
         "  --mode dual|lbo|si   --k N   --alpha A   --seed N   --resolution N (0: no decimation)\n"
         "  --centers N   --iterations N   --threads N (0: all cores)   --selection gated|region|descriptors|cost\n"
         "  --starts balls-and-wide-bumps|balls-and-wide-gaussians|gaussian|area-ball   --spectral-cuts N   --plane-cuts N\n"
         "  --indices FILE   also write the region's vertex indices (0-based, file order), one a line\n"
         "  --quiet          no progress on stderr\n";
}

inline std::size_t to_size(const std::string& flag, const std::string& s) {
  std::size_t used = 0;
  unsigned long long v = 0;
  try {
    v = std::stoull(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != s.size() || s.empty() || s[0] == '-') throw std::invalid_argument(flag + " expects a non-negative integer, got '" + s + "'");
  return static_cast<std::size_t>(v);
}

// The value named `m` among `choices` (name, value) of option `flag`; else an error listing
// the names ("--mode expects dual, lbo or si, got 'x'").
template <class T>
T pick(const std::string& flag, const std::string& m, std::initializer_list<std::pair<const char*, T>> choices) {
  std::string names;
  std::size_t i = 0;
  for (const auto& choice : choices) {
    if (m == choice.first) return choice.second;
    names += i == 0 ? "" : (i + 1 == choices.size() ? " or " : ", ");
    names += choice.first;
    ++i;
  }
  throw std::invalid_argument(flag + " expects " + names + ", got '" + m + "'");
}

inline Args parse(int argc, char** argv) {
  Args a;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      return argv[++i];
    };
    using dualspectra::Mode;
    using dualspectra::Selection;
    using dualspectra::StartShape;
    if (arg == "--mode") {
      a.options.mode = pick<Mode>(arg, value(), {{"dual", Mode::Dual}, {"lbo", Mode::Lbo}, {"si", Mode::Si}});
    } else if (arg == "--selection") {
      a.options.selection = pick<Selection>(arg, value(),
                                            {{"gated", Selection::Gated},
                                             {"region", Selection::Region},
                                             {"descriptors", Selection::Descriptors},
                                             {"cost", Selection::Cost}});
    } else if (arg == "--starts") {
      a.options.start_shape = pick<StartShape>(arg, value(),
                                               {{"balls-and-wide-bumps", StartShape::BallsAndWideBumps},
                                                {"balls-and-wide-gaussians", StartShape::BallsAndWideGaussians},
                                                {"gaussian", StartShape::Gaussian},
                                                {"area-ball", StartShape::AreaBall}});
    } else if (arg == "--k") a.options.k = to_size(arg, value());
    else if (arg == "--alpha") a.options.alpha = std::stod(value());
    else if (arg == "--seed") a.options.seed = to_size(arg, value());
    else if (arg == "--resolution") a.options.resolution = to_size(arg, value());
    else if (arg == "--centers") a.options.centers = to_size(arg, value());
    else if (arg == "--iterations") a.options.max_iterations = to_size(arg, value());
    else if (arg == "--threads") a.options.threads = to_size(arg, value());
    else if (arg == "--spectral-cuts") a.options.spectral_cuts = to_size(arg, value());
    else if (arg == "--plane-cuts") a.options.plane_cuts = to_size(arg, value());
    else if (arg == "--indices") a.indices = value();
    else if (arg == "--quiet") a.quiet = true;
    else if (arg.size() > 1 && arg[0] == '-') throw std::invalid_argument("unknown option " + arg);
    else positional.push_back(arg);
  }
  if (positional.size() != 3) throw std::invalid_argument("expected FULL PARTIAL OUTPUT");
  a.full = positional[0];
  a.partial = positional[1];
  a.output = positional[2];
  return a;
}

// Progress on stderr, one line per stage change.
inline dualspectra::ProgressCallback progress_printer(bool quiet) {
  if (quiet) return {};
  auto last = std::make_shared<std::string>();
  return [last](double fraction, std::string_view stage) {
    if (stage != *last) {
      *last = std::string(stage);
      std::fprintf(stderr, "  [%3.0f%%] %s\n", 100.0 * fraction, last->c_str());
    }
    return true;
  };
}

inline bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace example
