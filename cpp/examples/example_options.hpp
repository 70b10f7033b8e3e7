// Command-line options shared by the CGAL and OpenMesh examples. The localizer's flags are
// not listed here: they come from the core's option table (dualspectra::Options::schema()),
// one `--name VALUE` per option (`-` for `_`, as the CLI spells them), plus the generic
// `--option name=value`; so a new core option is a new flag without an edit here.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <dualspectra/dualspectra.hpp>

namespace example {

struct Args {
  std::string full, partial, output, indices;
  dualspectra::Options options;
  bool quiet = false;
  bool help = false;  // --help / -h: print usage_text() and exit
};

// One entry of the option schema, as text for --help.
struct OptionHelp {
  std::string name, label, doc, range, default_value;
};

// The schema's entries. A reader for exactly what Options::schema() writes (a JSON array of
// flat objects whose values are strings, numbers or arrays of strings), enough for --help.
inline std::vector<OptionHelp> schema_help() {
  const std::string s = dualspectra::Options::schema();
  std::vector<OptionHelp> out;
  std::size_t i = 0;
  auto skip_ws = [&] {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\n' || s[i] == '\t' || s[i] == '\r')) ++i;
  };
  auto read_string = [&]() {
    std::string t;
    for (++i; i < s.size() && s[i] != '"'; ++i) {
      if (s[i] == '\\' && i + 1 < s.size()) ++i;
      t += s[i];
    }
    ++i;
    return t;
  };
  auto read_value = [&]() -> std::string {  // a string, a number, or [strings] joined by '|'
    skip_ws();
    if (s[i] == '"') return read_string();
    if (s[i] == '[') {
      std::string t;
      for (++i, skip_ws(); i < s.size() && s[i] != ']'; skip_ws()) {
        if (s[i] == ',') { ++i; continue; }
        t += (t.empty() ? "" : "|") + read_string();
      }
      ++i;
      return t;
    }
    const std::size_t start = i;
    while (i < s.size() && s[i] != ',' && s[i] != '}') ++i;
    return s.substr(start, i - start);
  };
  for (; i < s.size(); ++i) {
    if (s[i] != '{') continue;
    OptionHelp h;
    std::string type, min, max, choices;
    for (++i, skip_ws(); i < s.size() && s[i] != '}'; skip_ws()) {
      if (s[i] == ',') { ++i; continue; }
      const std::string key = read_string();
      skip_ws();
      ++i;  // ':'
      const std::string value = read_value();
      if (key == "name") h.name = value;
      else if (key == "label") h.label = value;
      else if (key == "doc") h.doc = value;
      else if (key == "default") h.default_value = value;
      else if (key == "type") type = value;
      else if (key == "min") min = value;
      else if (key == "max") max = value;
      else if (key == "choices") choices = value;
    }
    h.range = type == "choice" ? choices : min + ".." + max;
    out.push_back(h);
  }
  return out;
}

inline std::string flag_of(std::string name) {
  for (auto& c : name)
    if (c == '_') c = '-';
  return "--" + name;
}

inline std::string usage_text() {
  std::string u =
      "  FULL PARTIAL OUTPUT [options]\n"
      "  FULL, PARTIAL: triangle meshes (OFF, PLY, OBJ, ...) read by the host library\n"
      "  OUTPUT: the full mesh with the region as vertex colours (red = region) and the score\n"
      "localizer options (the library's defaults unless given):\n";
  for (const auto& h : schema_help())
    u += "  " + flag_of(h.name) + " " + h.range + "  " + h.label + " (default " + h.default_value + "): " + h.doc + "\n";
  u += "  --option NAME=VALUE  any option by its name (as listed above, with _)\n"
       "  --indices FILE   also write the region's vertex indices (0-based, file order), one a line\n"
       "  --quiet          no progress on stderr\n"
       "  --help           this text\n";
  return u;
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
    if (arg == "--help" || arg == "-h") {
      a.help = true;
      return a;
    } else if (arg == "--indices") a.indices = value();
    else if (arg == "--quiet") a.quiet = true;
    else if (arg == "--option") {
      const std::string nv = value();
      const auto eq = nv.find('=');
      if (eq == std::string::npos) throw std::invalid_argument("--option expects NAME=VALUE, got '" + nv + "'");
      a.options.set(nv.substr(0, eq), nv.substr(eq + 1));
    } else if (arg.size() > 2 && arg.compare(0, 2, "--") == 0) {
      // --max-iterations 10 -> "max_iterations" = "10"; the library names an unknown option
      // or a value out of range (and lists the options).
      std::string name = arg.substr(2);
      for (auto& c : name)
        if (c == '-') c = '_';
      a.options.set(name, value());
    } else if (arg.size() > 1 && arg[0] == '-') throw std::invalid_argument("unknown flag " + arg);
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
