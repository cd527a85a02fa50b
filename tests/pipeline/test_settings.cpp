// The table of config keys (perclod/settings.h) against the YAML reader and
// settings_json: every key it names is read, no other key is, its `hashed`
// flag says what changes the settings hash, and its defaults are the reader's.
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "perclod/config.h"
#include "perclod/settings.h"
#include "test_util.h"

using namespace perclod;

namespace {
using test::error_of;

// The key of the top-level mapping a table key sits in: "crs_origin" for "crs_origin.lat".
std::string top_key(const std::string& key) { return key.substr(0, key.find('.')); }

// Whether YAML text sets top-level `key`.
bool sets(const std::string& yaml, const std::string& key) {
  return yaml.rfind(key + ":", 0) == 0 || yaml.find("\n" + key + ":") != std::string::npos;
}

// Two values of each key the reader accepts, which differ; "" leaves the key
// out (its default). Every key of config_settings() needs a line here.
struct Sample {
  const char* a;
  const char* b;
};
const std::map<std::string, Sample>& samples() {
  static const std::map<std::string, Sample> s = {
      {"model", {"model: other.obj", ""}},
      {"models", {"models: [m.obj, other.obj]", ""}},
      {"out", {"out: elsewhere", ""}},
      {"jobs", {"jobs: 3", ""}},
      {"memory_budget_mb", {"memory_budget_mb: 8000", ""}},
      {"memory_mb", {"memory_mb: 4000", ""}},
      {"up", {"up: z", ""}},
      {"scale", {"scale: 0.001", ""}},
      {"display", {"display: screen.yaml", ""}},
      {"distances", {"distances: [56, 132]", ""}},
      {"views", {"views: facades,top", ""}},
      {"facades", {"facades: [top]", "facades: facades"}},
      {"samples", {"samples: 4", ""}},
      {"spins", {"spins: 2", ""}},
      {"keep_unsampled_surface", {"keep_unsampled_surface: true", ""}},
      {"mask_per_sample", {"mask_per_sample: true", ""}},
      {"per_building", {"per_building: true", ""}},
      {"group_span", {"group_span: 1", ""}},
      {"own_views_alone", {"own_views_alone: false", ""}},
      {"combine_views", {"combine_views: any", ""}},
      {"tracer", {"tracer: embree", ""}},
      {"verify", {"verify: true", ""}},
      {"ratio", {"ratio: 0.25", ""}},
      {"simplify", {"simplify: paper", ""}},
      {"e_perceptible", {"e_perceptible: 0.25", ""}},
      {"e_imperceptible", {"e_imperceptible: 2", ""}},
      {"e_undisplayable", {"e_undisplayable: 4", ""}},
      {"keep_undisplayable", {"keep_undisplayable: false", ""}},
      {"k", {"k: 2", ""}},
      {"target", {"simplify: qem\ntarget: 500", "simplify: qem\ntarget: 600"}},
      {"format", {"format: glb", ""}},
      {"judge_views", {"judge_views: none", ""}},
      {"judge_buildings_alone", {"judge_buildings_alone: false", ""}},
      {"max_changed", {"max_changed: 0.05", ""}},
      {"max_silhouette", {"max_silhouette: 0.02", ""}},
      {"min_ssim", {"min_ssim: 0.9", ""}},
      {"max_visible", {"max_visible: 2", ""}},
      {"max_visible_local", {"max_visible_local: 1", ""}},
      {"strict", {"strict: true", ""}},
      {"tighten_to_limits", {"tighten_to_limits: false", ""}},
      {"free_topology", {"free_topology: false", ""}},
      {"explain", {"explain: true", ""}},
      {"fidelity_target", {"fidelity_target: {}", ""}},
      {"fidelity_target.max_changed",
       {"fidelity_target: {max_changed: 0.05}", "fidelity_target: {max_changed: 0.04}"}},
      {"fidelity_target.max_silhouette",
       {"fidelity_target: {max_silhouette: 0.05}", "fidelity_target: {max_silhouette: 0.04}"}},
      {"fidelity_target.min_ssim", {"fidelity_target: {min_ssim: 0.9}", "fidelity_target: {min_ssim: 0.8}"}},
      {"fidelity_target.max_visible", {"fidelity_target: {max_visible: 1}", "fidelity_target: {max_visible: 0.5}"}},
      {"fidelity_target.max_visible_local",
       {"fidelity_target: {max_visible_local: 1}", "fidelity_target: {max_visible_local: 2}"}},
      {"cityjson_lod", {"cityjson_lod: \"2\"", ""}},
      {"crs", {"crs: EPSG:28992", ""}},
      {"crs_origin", {"crs_origin: {lat: 48.7, lon: 11.4}", ""}},
      {"crs_origin.lat", {"crs_origin: {lat: 48.7, lon: 11.4}", "crs_origin: {lat: 48.8, lon: 11.4}"}},
      {"crs_origin.lon", {"crs_origin: {lat: 48.7, lon: 11.4}", "crs_origin: {lat: 48.7, lon: 11.5}"}},
      {"crs_origin.height", {"crs_origin: {lat: 48.7, lon: 11.4, height: 380}", "crs_origin: {lat: 48.7, lon: 11.4}"}},
      {"tileset", {"tileset: false", ""}},
      {"debug_images", {"debug_images: false", ""}},
      {"marking_near", {"marking_near: true", ""}},
  };
  return s;
}

// A folder with two models and a display profile, and configs made in it.
struct Folder {
  test::TempDir dir{"settings"};
  int written = 0;
  Folder() {
    for (const char* f : {"m.obj", "other.obj"}) dir.file(f, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    dir.file("screen.yaml", "width: 800\nheight: 600\ndpi: 96\nviewer_distance_m: 0.6\n");
  }
  std::string path(const std::string& yaml, bool batch) {
    std::string text = yaml + "\n";
    if (!sets(yaml, "distances")) text += "distances: [10]\n";
    if (batch && !sets(yaml, "models")) text += "models: [m.obj]\n";
    if (!batch && !sets(yaml, "model")) text += "model: m.obj\n";
    return dir.file("c" + std::to_string(written++) + ".yaml", text);
  }
  // `yaml` with the lines a config needs around it: a batch for the batch's
  // own keys (top_only), else one model.
  ConfigFile load(const std::string& yaml, bool batch) { return load_config_file(path(yaml, batch)); }
};

// What a config decides: the hashed settings and the rest.
std::string fingerprint(const ConfigFile& f) {
  const BatchConfig& c = f.models.at(0).config;
  return settings_json(c).dump() + " out=" + f.out + " jobs=" + std::to_string(f.jobs) +
         " budget=" + std::to_string(f.memory_budget_mb) + " models=" + std::to_string(f.models.size()) +
         " model=" + c.model + " memory_mb=" + std::to_string(c.memory_mb) + " strict=" + std::to_string(c.strict);
}

}  // namespace

TEST(Settings, TableKeysAreUniqueAndWellFormed) {
  std::set<std::string> keys;
  for (const SettingSpec& s : config_settings()) {
    EXPECT_TRUE(keys.insert(s.key).second) << s.key << " twice";
    EXPECT_TRUE(*s.type && *s.default_text && *s.help) << s.key;
    const std::string key = s.key;
    if (key.find('.') != std::string::npos) {
      const SettingSpec* parent = find_setting(config_settings(), top_key(key));
      ASSERT_NE(parent, nullptr) << key;
      EXPECT_STREQ(parent->type, "mapping") << key;
      EXPECT_EQ(parent->hashed, s.hashed) << key;
    }
    if (s.alias_of) {
      const SettingSpec* of = find_setting(config_settings(), s.alias_of);
      ASSERT_NE(of, nullptr) << key;
      EXPECT_EQ(of->alias_of, nullptr) << key;
    }
  }
  EXPECT_STREQ(config_setting("facades").alias_of, "views");
  EXPECT_THROW(config_setting("no_such_key"), std::logic_error);
}

// Every key of the table is read: each sample value loads, and the two
// values of a key make different configs. The keys sampled are the table's.
TEST(Settings, EveryKeyOfTheTableIsRead) {
  std::set<std::string> table, sampled;
  for (const SettingSpec& s : config_settings()) table.insert(s.key);
  for (const auto& kv : samples()) sampled.insert(kv.first);
  EXPECT_EQ(sampled, table) << "a key of config_settings() without a sample here, or a sample of no key";
  Folder f;
  for (const SettingSpec& s : config_settings()) {
    auto it = samples().find(s.key);
    if (it == samples().end()) continue;
    const Sample& v = it->second;
    EXPECT_TRUE(sets(v.a, top_key(s.key))) << s.key;
    std::string a, b;
    const std::string err = error_of([&] {
      a = fingerprint(f.load(v.a, s.top_only));
      b = fingerprint(f.load(v.b, s.top_only));
    });
    ASSERT_EQ(err, "") << s.key;
    EXPECT_NE(a, b) << s.key << ": '" << v.a << "' and '" << v.b << "' load alike";
  }
}

// A key is `hashed` exactly when changing it changes settings_json.
TEST(Settings, HashedKeysAreTheOnesThatChangeTheSettingsHash) {
  Folder f;
  for (const SettingSpec& s : config_settings()) {
    auto it = samples().find(s.key);
    if (it == samples().end()) continue;
    const nlohmann::json a = settings_json(f.load(it->second.a, s.top_only).models.at(0).config);
    const nlohmann::json b = settings_json(f.load(it->second.b, s.top_only).models.at(0).config);
    EXPECT_EQ(a != b, s.hashed) << s.key << (s.hashed ? " is hashed but does not change" : " is not hashed but changes")
                                << " settings_json:\n" << a.dump() << "\n" << b.dump();
  }
}

// With every key that joins only when set, settings_json holds exactly the
// table's hashed keys (the nested and the old names inside their mappings),
// and its display the display profile's keys.
TEST(Settings, SettingsJsonHoldsTheHashedKeys) {
  Folder f;
  const nlohmann::json s = settings_json(
      f.load("min_ssim: 0.9\nmax_visible: 1\nmax_visible_local: 1\nmask_per_sample: true\ne_undisplayable: 4\nexplain: true\n"
             "group_span: 0.5\n"
             "fidelity_target: {min_ssim: 0.95}\ncrs: EPSG:28992\ndisplay: screen.yaml",
             false)
          .models.at(0)
          .config);
  std::set<std::string> hashed, written, display, display_written;
  for (const SettingSpec& k : config_settings())
    if (k.hashed && !k.alias_of && !std::strchr(k.key, '.')) hashed.insert(k.key);
  for (const auto& kv : s.items()) written.insert(kv.key());
  EXPECT_EQ(written, hashed);
  for (const SettingSpec& k : display_settings()) display.insert(k.key);
  for (const auto& kv : s["display"].items()) display_written.insert(kv.key());
  EXPECT_EQ(display_written, display);
  EXPECT_EQ(s["display"]["width"], 800);
  EXPECT_EQ(s["fidelity_target"]["min_ssim"], 0.95);
}

// A default that is a value ("0.5", "auto", "out": not "(required)") is the
// reader's: writing it into a config changes nothing.
TEST(Settings, DefaultsAreTheReadersDefaults) {
  Folder f;
  size_t checked = 0;
  for (const SettingSpec& s : config_settings()) {
    const std::string d = s.default_text, key = s.key;
    if (d[0] == '(' || key.find('.') != std::string::npos) continue;
    const std::string value = d.substr(0, d.find(" ("));
    std::string with, without;
    const std::string err = error_of([&] {
      with = fingerprint(f.load(key + ": " + value, s.top_only));
      without = fingerprint(f.load("", s.top_only));
    });
    EXPECT_EQ(err, "") << key << ": " << value;
    EXPECT_EQ(with, without) << key << ": the table's default '" << value << "' is not the reader's";
    ++checked;
  }
  EXPECT_GE(checked, 30u);
  // The comparison sees a value that is not the default.
  EXPECT_NE(fingerprint(f.load("ratio: 0.4", false)), fingerprint(f.load("", false)));
  EXPECT_NE(fingerprint(f.load("strict: true", false)), fingerprint(f.load("", false)));
  // A nested default names the key it takes its value from.
  for (const char* k : {"fidelity_target.max_changed", "fidelity_target.max_silhouette", "fidelity_target.min_ssim"})
    EXPECT_NE(find_setting(config_settings(), config_setting(k).default_text), nullptr) << k;
}

// A key not in the table is refused at every level, naming the file; the
// batch's own keys are refused in a models entry.
TEST(Settings, UnknownKeysAreRefusedNamingTheFile) {
  Folder f;
  auto refused = [&](const std::string& yaml, bool batch, const std::string& says) {
    const std::string p = f.path(yaml, batch);
    const std::string err = error_of([&] { load_config_file(p); });
    EXPECT_EQ(err.rfind(p + ": ", 0), 0u) << yaml << ": " << err;
    EXPECT_NE(err.find(says), std::string::npos) << yaml << ": " << err;
    return err;
  };
  const std::string err = refused("no_such_setting: 1", false, "unknown key 'no_such_setting' (known keys: ");
  for (const SettingSpec& s : config_settings()) {
    if (std::strchr(s.key, '.')) continue;  // listed in their mapping's error
    EXPECT_NE(err.find(s.key), std::string::npos) << s.key << " not listed: " << err;
  }
  refused("ratoi: 0.5", false, "unknown key 'ratoi' (did you mean 'ratio'?)");
  refused("fidelity_target: {max_changes: 0.1}", false, "unknown key 'max_changes' (did you mean 'max_changed'?)");
  refused("crs_origin: {lat: 1, lon: 2, altitude: 3}", false, "unknown key 'altitude'");
  refused("models: [{model: m.obj, jobs: 2}]", true, "models[0]: unknown key 'jobs'");
  refused("models: [{model: m.obj, out: x}]", true, "models[0]: unknown key 'out'");
}

// The display profile table: every key is read, the required ones are
// required, and any other key is refused naming the file.
TEST(Settings, DisplayProfileKeysAreTheTables) {
  Folder f;
  const std::map<std::string, std::string> values = {{"name", "screen"}, {"width", "800"},
                                                     {"height", "600"},  {"dpi", "96"},
                                                     {"viewer_distance_m", "0.6"}, {"fov_y_deg", "40"}};
  std::set<std::string> table, given;
  std::string all;
  for (const SettingSpec& s : display_settings()) table.insert(s.key);
  for (const auto& kv : values) given.insert(kv.first), all += kv.first + ": " + kv.second + "\n";
  EXPECT_EQ(given, table);
  const DisplayProfile d = load_display_profile(f.dir.file("all.yaml", all));
  EXPECT_EQ(d.name, "screen");
  EXPECT_EQ(d.width, 800);
  EXPECT_EQ(d.fov_y_override_deg, 40);
  for (const SettingSpec& s : display_settings()) {
    std::string without;
    for (const auto& kv : values)
      if (kv.first != s.key) without += kv.first + ": " + kv.second + "\n";
    const std::string p = f.dir.file("without.yaml", without);
    const std::string err = error_of([&] { load_display_profile(p); });
    const bool required = std::strcmp(s.default_text, "(required)") == 0;
    EXPECT_EQ(err, required ? p + ": '" + s.key + "' is required" : "") << s.key;
  }
  const std::string p = f.dir.file("bad.yaml", all + "gamma: 2.2\n");
  const std::string err = error_of([&] { load_display_profile(p); });
  EXPECT_EQ(err.rfind(p + ": unknown key 'gamma'", 0), 0u) << err;
}
