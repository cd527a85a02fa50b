// perclod/settings.h - the one table of config keys (docs/usage.md#config-keys)
// and of display profile keys (docs/usage.md#display-profiles).
//
// Each key is declared here once. The YAML reader takes its known keys from
// these tables, settings_json the keys that enter the settings hash, the CLI
// the help of the options that set a key, and a test holds the tables in
// docs/usage.md to them.
#pragma once

#include <string_view>
#include <vector>

namespace perclod {

struct SettingSpec {
  const char* key;           // "ratio"; a key of a nested mapping is dotted: "crs_origin.lat"
  const char* type;          // "number (px)", "boolean", "view set: string or list", ...
  const char* default_text;  // "0.5"; in parentheses when it is no value: "(required)", "(none)"
  const char* allowed;       // "0..1", "`octree`, `embree`"; "" when the type says it all
  const char* help;          // one sentence: what the key does (the CLI's help of its option)
  bool hashed;               // enters settings_json and so the settings hash (an output made under
                             // other values of it is out of date)
  bool top_only;             // the batch's own keys: a config's top level only, not a `models:` entry
  const char* alias_of;      // an old name: the key it stands for (nullptr for the others)
};

// Every key of a config file: a model's keys, the batch's (top_only) and
// the old alias `facades`, in the order of docs/usage.md#config-keys.
const std::vector<SettingSpec>& config_settings();
// Every key of a display profile file (configs/displays/*.yaml).
const std::vector<SettingSpec>& display_settings();

// The entry of `key` in `table`, or nullptr.
const SettingSpec* find_setting(const std::vector<SettingSpec>& table, std::string_view key);
// The entry of a config key; throws std::logic_error naming a key the table
// lacks (a programming error: a CLI option naming a key that does not exist).
const SettingSpec& config_setting(std::string_view key);

}  // namespace perclod
