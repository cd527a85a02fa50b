#include "common.h"

#include "perclod/outputs.h"
#include "perclod/settings.h"

#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

namespace perclod::cli {

void ModelArgs::add(CLI::App* cmd) {
  cmd->add_option("MODEL", path, "Model file: OBJ, CityJSON, PLY, glTF/GLB, STL, IFC, DAE, FBX")->required();
  cmd->add_option("--up", up, key_help("up", key_default("up")))
      ->check(CLI::IsMember({"y", "z", "Y", "Z"}));
  cmd->add_option("--scale", scale, key_help("scale"))->check(kPositive);
  cmd->add_option("--cityjson-lod", cityjson_lod, key_help("cityjson_lod", "default: each object's highest"));
}

Scene ModelArgs::load(LoadReport* report, bool quiet) const {
  LoadOptions o;
  o.scale = scale;
  o.cityjson_lod = cityjson_lod;
  return load_model(path, o, report, quiet);
}

Scene load_model(const std::string& path, const LoadOptions& options, LoadReport* report, bool quiet) {
  LoadReport rep;
  Scene s = load_scene(path, options, &rep);
  if (!quiet) {
    std::fprintf(stderr, "loaded %s: %zu triangles, %zu components in %.2f s", path.c_str(), s.triangle_count(),
                 s.component_count(), rep.seconds);
    if (rep.degenerate_triangles) std::fprintf(stderr, " (%zu degenerate triangles kept)", rep.degenerate_triangles);
    if (rep.polygons_fanned)
      std::fprintf(stderr, " (%zu polygons ear clipping could not finish: their rest is a fan that may overlap)",
                   rep.polygons_fanned);
    std::fprintf(stderr, "\n");
  }
  if (report) *report = rep;
  return s;
}

void DisplayArgs::add(CLI::App* cmd) {
  cmd->add_option("--display", path, key_help("display", "default: the paper's 1280x1024, 86.27 dpi, 0.5 m"))
      ->check(kNotEmpty);
}

DisplayProfile DisplayArgs::profile() const {
  return path.empty() ? default_display_profile() : load_display_profile(path);
}

std::vector<double> check_distances(const std::vector<double>& d) {
  if (d.empty()) throw OptionError("--distance: give at least one distance");
  for (double x : d)
    if (const std::string p = distance_problem(x); !p.empty()) throw OptionError("--distance: " + p);
  check_distinct_tags(d);
  return d;
}

std::vector<std::string> views_option(const std::string& spec, UpAxis up) {
  try {
    return parse_views(spec, up);
  } catch (const std::invalid_argument& e) {
    throw OptionError(std::string("--views: ") + e.what());
  }
}

namespace {

bool parse_number(const std::string& s, double& v) {
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return !s.empty() && end == s.c_str() + s.size() && std::isfinite(v);
}

std::vector<std::string>& error_files() {
  static std::vector<std::string> files;
  return files;
}

// True when `what` already starts with a file name: "FILE: ..." or "FILE:LINE: ...".
bool names_a_file(const std::string& what) {
  for (const auto& f : error_files())
    if (!f.empty() && what.compare(0, f.size() + 1, f + ":") == 0) return true;
  size_t colon = what.find(':');
  if (colon == std::string::npos || colon == 0) return false;
  std::string head = what.substr(0, colon);
  return head.find(' ') == std::string::npos && head.find('\'') == std::string::npos &&
         (head.find('/') != std::string::npos || head.find('.') != std::string::npos);
}

}  // namespace

const CLI::Validator kPositive(
    [](std::string& s) -> std::string {
      double v;
      return parse_number(s, v) && v > 0 ? "" : "must be a positive number, got '" + s + "'";
    },
    "POSITIVE");

const CLI::Validator kNonNegative(
    [](std::string& s) -> std::string {
      double v;
      return parse_number(s, v) && v >= 0 ? "" : "must be a number >= 0, got '" + s + "'";
    },
    "NONNEGATIVE");

const CLI::Validator kNotEmpty([](std::string& s) -> std::string { return s.empty() ? "must not be empty" : ""; },
                               "DIR");

CLI::Validator in_range(double lo, double hi) {
  std::ostringstream desc;
  desc << "[" << lo << " - " << hi << "]";
  return CLI::Validator(
      [lo, hi, d = desc.str()](std::string& s) -> std::string {
        double v;
        return parse_number(s, v) && v >= lo && v <= hi ? "" : "must be a number in " + d + ", got '" + s + "'";
      },
      desc.str());
}

std::string key_help(const char* key, const std::string& note) {
  const std::string text = std::string(config_setting(key).help) + (note.empty() ? "" : " (" + note + ")");
  // Lines of at most kWidth characters, broken at spaces (CLI11 indents them).
  constexpr size_t kWidth = 90;
  std::string out;
  size_t line = 0;
  std::istringstream words(text);
  for (std::string w; words >> w;) {
    if (line > 0 && line + 1 + w.size() > kWidth) {
      out += '\n';
      line = 0;
    } else if (line > 0) {
      out += ' ';
      ++line;
    }
    out += w;
    line += w.size();
  }
  return out;
}

std::string key_default(const char* key) { return std::string("default ") + config_setting(key).default_text; }

CLI::Validator samples_check() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        try {
          parse_samples(s);
          return "";
        } catch (const std::invalid_argument& e) {
          return e.what();
        }
      },
      "auto|1|2|4|8|9|16");
}

void set_error_files(std::vector<std::string> files) { error_files() = std::move(files); }

std::string error_message(const std::string& what) {
  if (error_files().empty() || error_files()[0].empty() || names_a_file(what)) return what;
  return error_files()[0] + ": " + what;
}

void require_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw std::runtime_error(path + ": no such file");
}


void print_progress(const std::string& message) { std::fprintf(stderr, "%s\n", message.c_str()); }

void print_json(const nlohmann::json& j) { std::cout << j.dump(2) << std::endl; }

}  // namespace perclod::cli
