// Options and helpers shared by the perclod subcommands.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <stdexcept>
#include <string>
#include <vector>

#include "perclod/config.h"
#include "perclod/load.h"
#include "perclod/views.h"

namespace perclod::cli {

// MODEL plus --up and --scale.
struct ModelArgs {
  std::string path;
  std::string up = "y";
  double scale = 1.0;
  std::string cityjson_lod;
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

// parse_facades for the --facade option: a bad list is an OptionError.
std::vector<std::string> views_option(const std::string& spec, UpAxis up);

// "56,132,427" or repeated --distance.
std::vector<double> check_distances(const std::vector<double>& d);

// A bad option value found by a command (not by CLI11): main() prints it as
// "perclod: error: <message>" (no file) with exit status 1.
struct OptionError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// The help of an option that sets config key `key`: the key's help in the
// table of settings (perclod/settings.h, docs/usage.md#config-keys), then
// `note` in parentheses ("default 0.5", "overrides the config's ratio"),
// wrapped for --help. So an option's help and the docs say the same.
std::string key_help(const char* key, const std::string& note = "");
// "default <the key's default>" for key_help's note.
std::string key_default(const char* key);

// Validators whose messages read "must be ..., got 'X'" (CLI11 prefixes the
// option name), instead of CLI11's "Value 0 not in range 2.2e-308 to 1.8e308".
extern const CLI::Validator kPositive;     // a finite number > 0
extern const CLI::Validator kNonNegative;  // a finite number >= 0
extern const CLI::Validator kNotEmpty;     // a non-empty string (output directories)
CLI::Validator in_range(double lo, double hi);
CLI::Validator samples_check();          // auto, 1, 2, 4, 8, 9 or 16

// The files an error is about, for messages that name none (e.g. "scene:
// index out of range" from the library): main() prefixes the first. Each
// command sets them before its work (model, config, image, ...).
void set_error_files(std::vector<std::string> files);
// "perclod: error: FILE: what" as main() prints it (without the prefix).
std::string error_message(const std::string& what);

// Throws "PATH: no such file" unless PATH is a regular file (checked before
// a model is loaded, so a bad --labels fails at once).
void require_file(const std::string& path);

// Progress lines to stderr.
void print_progress(const std::string& message);
void print_json(const nlohmann::json& j);

}  // namespace perclod::cli
