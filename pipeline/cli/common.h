// Options and helpers shared by the perclod subcommands.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <string>

#include "perclod/config.h"
#include "perclod/load.h"
#include "perclod/views.h"

namespace perclod::cli {

// MODEL plus --up and --scale.
struct ModelArgs {
  std::string path;
  std::string up = "y";
  double scale = 1.0;
  void add(CLI::App* cmd);
  // Loads the model; prints a one-line summary to stderr unless quiet.
  Scene load(LoadReport* report = nullptr, bool quiet = false) const;
  UpAxis up_axis() const { return parse_up_axis(up); }
};

// load_scene, then (unless quiet) a one-line summary on stderr.
Scene load_model(const std::string& path, const LoadOptions& options, LoadReport* report = nullptr,
                 bool quiet = false);

// --display FILE (a configs/displays/*.yaml profile).
struct DisplayArgs {
  std::string path;
  void add(CLI::App* cmd);
  DisplayProfile profile() const;
};

// "56,132,427" or repeated --distance.
std::vector<double> check_distances(const std::vector<double>& d);

// Progress lines to stderr.
void print_progress(const std::string& message);
nlohmann::json to_json(const LoadReport& r);
void print_json(const nlohmann::json& j);

}  // namespace perclod::cli
