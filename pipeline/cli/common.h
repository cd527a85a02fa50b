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

// --display FILE (a configs/displays/*.yaml profile).
struct DisplayArgs {
  std::string path;
  void add(CLI::App* cmd);
  DisplayProfile profile() const;
};

// "56,132,427" or repeated --distance.
std::vector<double> check_distances(const std::vector<double>& d);

std::string file_stem(const std::string& path);
std::string distance_tag(double d);  // "56m", "12.5m"
nlohmann::json to_json(const LoadReport& r);
void print_json(const nlohmann::json& j);

}  // namespace perclod::cli
