// Batch configs, shards, LOD ranges, the ENU frame and the GLB exports.
#include <gtest/gtest.h>

#include <cstring>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "perclod/batch.h"
#include "perclod/model_exports.h"
#include "perclod/run_model.h"
#include "perclod/config.h"
#include "perclod/export.h"
#include "perclod/load.h"
#include "perclod/outputs.h"
#include "test_util.h"

using namespace perclod;
namespace fs = std::filesystem;

namespace {
using test::error_of;

// A folder with three model files in two subfolders and a config using them.
struct BatchFolder {
  test::TempDir dir{"batchcfg"};
  BatchFolder() {
    fs::create_directories(dir.path / "city" / "a");
    fs::create_directories(dir.path / "city" / "b");
    for (const char* f : {"city/a/house.obj", "city/b/house.obj", "city/b/tower.obj", "city/b/notes.txt",
                          "city/a/house_report.json"})
      std::ofstream(dir.path / f) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  }
  // A batch config `name` at 56 m: city/a as it is, then one entry per
  // override, alternately city/b/tower.obj and city/a/house.obj with those
  // settings.
  ConfigFile models_with(const std::string& name, const std::vector<std::string>& overrides) {
    std::string text = "distances: [56]\nmodels:\n  - city/a\n";
    for (size_t i = 0; i < overrides.size(); ++i)
      text += std::string("  - {model: ") + (i % 2 ? "city/a/house.obj" : "city/b/tower.obj") + ", " + overrides[i] +
              "}\n";
    return load_config_file(dir.file(name, text));
  }
  // Loading a one-model config with `settings` fails with an error naming
  // the file and holding `says`.
  void expect_refused(const std::string& settings, const std::string& says) {
    const std::string err = error_of([&] {
      load_config_file(dir.file("bad.yaml", "distances: [56]\nmodel: city/a/house.obj\n" + settings));
    });
    EXPECT_NE(err.find("bad.yaml"), std::string::npos) << settings << ": " << err;
    EXPECT_NE(err.find(says), std::string::npos) << settings << ": " << err;
  }
};

}  // namespace

TEST(BatchConfig, ModelsListGlobsFoldersAndOverrides) {
  BatchFolder b;
  const std::string cfg = b.dir.file("batch.yaml",
                                     "distances: [56, 132]\nsamples: 2\nout: results\njobs: 2\n"
                                     "models:\n"
                                     "  - city/b/*.obj\n"
                                     "  - {model: city/a, up: z, distances: [427], memory_mb: 4000}\n");
  ConfigFile f = load_config_file(cfg);
  ASSERT_TRUE(f.batch);
  EXPECT_EQ(f.jobs, 2);
  ASSERT_EQ(f.models.size(), 3u);  // notes.txt and a report are not model files
  // Two files share the stem "house": their folders take the parent's name.
  EXPECT_EQ(f.models[0].name, "b_house");
  EXPECT_EQ(f.models[1].name, "tower");
  EXPECT_EQ(f.models[2].name, "a_house");
  EXPECT_EQ(f.models[0].config.up, UpAxis::Y);
  EXPECT_EQ(f.models[0].config.distances, (std::vector<double>{56, 132}));
  EXPECT_EQ(f.models[2].config.up, UpAxis::Z);
  EXPECT_EQ(f.models[2].config.distances, (std::vector<double>{427}));
  EXPECT_EQ(f.models[2].config.samples, 2);  // the top level's, not overridden
  EXPECT_EQ(f.models[2].config.memory_mb, 4000);
  EXPECT_EQ(f.models[0].config.memory_mb, 0);  // estimated from the file
  for (const auto& m : f.models) {
    EXPECT_TRUE(fs::path(m.config.model).is_absolute()) << m.config.model;
    EXPECT_TRUE(fs::exists(m.config.model)) << m.config.model;
    EXPECT_EQ(m.config.out, "results");  // like a single model's out: from the working directory
  }
  // The settings hash sees an override; the same settings hash alike.
  EXPECT_NE(hash_text(settings_json(f.models[0].config).dump()), hash_text(settings_json(f.models[2].config).dump()));
  EXPECT_EQ(hash_text(settings_json(f.models[0].config).dump()), hash_text(settings_json(f.models[1].config).dump()));
  BatchConfig more = f.models[0].config;
  more.memory_mb = 9000;  // scheduling only: the outputs stay up to date
  EXPECT_EQ(hash_text(settings_json(more).dump()), hash_text(settings_json(f.models[0].config).dump()));
  // A single-model reader refuses a batch, naming the file.
  EXPECT_NE(error_of([&] { load_batch_config(cfg); }).find("names several models"), std::string::npos);
}

TEST(BatchConfig, BadEntriesNameTheEntryAndWhatIsWrong) {
  BatchFolder b;
  auto err = [&](const std::string& body) {
    return error_of([&] { load_config_file(b.dir.file("bad.yaml", "distances: [56]\n" + body)); });
  };
  EXPECT_NE(err("models:\n  - city/none/*.obj\n").find("models[0]: 'city/none/*.obj' matches no model file"),
            std::string::npos);
  EXPECT_NE(err("models: []\n").find("non-empty list"), std::string::npos);
  EXPECT_NE(err("models:\n  - city/a/house.obj\n  - {model: city/b/tower.obj, ratio: 7}\n").find("models[1]: 'ratio'"),
            std::string::npos);
  EXPECT_NE(err("models:\n  - {up: z}\n").find("models[0]: 'model' is required"), std::string::npos);
  EXPECT_NE(err("models:\n  - {model: city/a, memory_mb: -5}\n").find("models[0]: 'memory_mb'"), std::string::npos);
  EXPECT_NE(err("models:\n  - {model: city/a, out: x}\n").find("models[0]: unknown key 'out'"), std::string::npos);
  EXPECT_NE(err("models:\n  - city/missing.obj\n").find("models[0]: model"), std::string::npos);
  EXPECT_NE(err("model: city/a/house.obj\nmodels:\n  - city/a\n").find("not both"), std::string::npos);
  EXPECT_NE(err("model: city/a/house.obj\njobs: 2\n").find("apply only to a batch"), std::string::npos);
  EXPECT_NE(err("jobs: 0\nmodels:\n  - city/a\n").find("'jobs' must be 1..64"), std::string::npos);
  EXPECT_NE(err("crs_origin: {lat: 95, lon: 0}\nmodels:\n  - city/a\n").find("'crs_origin'"), std::string::npos);
}

// min_ssim changes the settings hash only when it is set: configs without it
// (and the batches a manifest resumes) keep the hash they had before the key.
TEST(BatchConfig, MinSsimJoinsTheSettingsHashOnlyWhenSet) {
  BatchFolder b;
  ConfigFile f = load_config_file(b.dir.file("batch.yaml", "distances: [56]\nmodel: city/a/house.obj\n"));
  const BatchConfig& plain = f.models[0].config;
  const nlohmann::json s = settings_json(plain);
  EXPECT_FALSE(s.contains("min_ssim"));
  BatchConfig with = plain;
  with.min_ssim = 0.95;
  EXPECT_EQ(settings_json(with)["min_ssim"], 0.95);
  EXPECT_NE(hash_text(settings_json(with).dump()), hash_text(s.dump()));
  BatchConfig target = plain;
  target.fidelity_target = true;
  EXPECT_FALSE(settings_json(target)["fidelity_target"].contains("min_ssim"));
  target.target_min_ssim = 0.95;
  EXPECT_EQ(settings_json(target)["fidelity_target"]["min_ssim"], 0.95);
}

// keep_unsampled_surface reaches the labelling job, per model, and changes
// the settings hash (a batch redoes the models it changes); a value that is
// not a boolean names the key.
TEST(BatchConfig, KeepUnsampledSurfaceReachesTheLabellingJob) {
  BatchFolder b;
  ConfigFile f = b.models_with("batch.yaml", {"keep_unsampled_surface: true"});
  ASSERT_EQ(f.models.size(), 2u);
  EXPECT_FALSE(f.models[0].config.keep_unsampled_surface);
  EXPECT_TRUE(f.models[1].config.keep_unsampled_surface);
  EXPECT_FALSE(lod_job(f.models[0].config).label.keep_unsampled_surface);
  EXPECT_TRUE(lod_job(f.models[1].config).label.keep_unsampled_surface);
  BatchConfig on = f.models[0].config;
  on.keep_unsampled_surface = true;
  EXPECT_NE(hash_text(settings_json(on).dump()), hash_text(settings_json(f.models[0].config).dump()));
  b.expect_refused("keep_unsampled_surface: often\n", "'keep_unsampled_surface'");
}

// mask_per_sample reaches the labelling job and joins the settings hash only
// when set (older batches keep their hashes); a value that is not a boolean,
// or the pair with keep_unsampled_surface, is an error naming the file.
TEST(BatchConfig, MaskPerSampleReachesTheLabellingJob) {
  BatchFolder b;
  ConfigFile f = b.models_with("batch.yaml", {"mask_per_sample: true"});
  ASSERT_EQ(f.models.size(), 2u);
  EXPECT_FALSE(lod_job(f.models[0].config).label.mask_per_sample);
  EXPECT_TRUE(lod_job(f.models[1].config).label.mask_per_sample);
  EXPECT_FALSE(settings_json(f.models[0].config).contains("mask_per_sample"));
  EXPECT_EQ(settings_json(f.models[1].config)["mask_per_sample"], true);
  for (const char* bad : {"mask_per_sample: sometimes\n", "mask_per_sample: true\nkeep_unsampled_surface: true\n"})
    b.expect_refused(bad, "'mask_per_sample'");
}

// samples: 9 and 16 are the ordered grids read from one refined render;
// with keep_unsampled_surface they are refused, naming the file and key.
TEST(BatchConfig, GridSamplesReachTheLabellingJob) {
  BatchFolder b;
  ConfigFile f = load_config_file(
      b.dir.file("grid.yaml", "distances: [56]\nmodels:\n  - {model: city/a/house.obj, samples: 16}\n"));
  ASSERT_EQ(f.models.size(), 1u);
  EXPECT_EQ(lod_job(f.models[0].config).label.samples, 16);
  EXPECT_EQ(sample_grid(16), 4);
  EXPECT_EQ(sample_grid(9), 3);
  EXPECT_EQ(sample_grid(8), 0);
  b.expect_refused("samples: 9\nkeep_unsampled_surface: true\n", "'keep_unsampled_surface'");
}

// samples: auto (the default) reaches the labelling job as kAutoSamples and
// joins the settings hash as "auto" (a count as the number it always was);
// a count that is no pattern, or a list, is an error naming the file and
// the key.
TEST(BatchConfig, AutoSamplesAreTheDefaultAndParse) {
  BatchFolder b;
  ConfigFile f = b.models_with("auto.yaml", {"samples: auto", "samples: 4"});
  ASSERT_EQ(f.models.size(), 3u);
  EXPECT_EQ(lod_job(f.models[0].config).label.samples, kAutoSamples);
  EXPECT_EQ(lod_job(f.models[1].config).label.samples, kAutoSamples);
  EXPECT_EQ(lod_job(f.models[2].config).label.samples, 4);
  EXPECT_EQ(settings_json(f.models[0].config)["samples"], "auto");
  EXPECT_EQ(settings_json(f.models[2].config)["samples"], 4);  // a number stays one: older batches keep their hashes
  EXPECT_NE(hash_text(settings_json(f.models[0].config).dump()), hash_text(settings_json(f.models[2].config).dump()));
  for (const char* bad : {"samples: 3\n", "samples: [4]\n", "samples: often\n"}) b.expect_refused(bad, "'samples'");
}

TEST(BatchConfig, KeepUndisplayableIsAutoByDefaultAndParses) {
  BatchFolder b;
  ConfigFile f =
      b.models_with("keep.yaml", {"keep_undisplayable: false", "keep_undisplayable: true", "e_undisplayable: 2"});
  ASSERT_EQ(f.models.size(), 4u);
  const LodJob automatic = lod_job(f.models[0].config), deleting = lod_job(f.models[1].config),
               keeping = lod_job(f.models[2].config), bounded = lod_job(f.models[3].config);
  EXPECT_TRUE(automatic.undisplayable_auto);
  EXPECT_TRUE(automatic.simplify.delete_undisplayable);  // until the exposure says otherwise
  EXPECT_FALSE(deleting.undisplayable_auto);
  EXPECT_TRUE(deleting.simplify.delete_undisplayable);
  EXPECT_FALSE(keeping.simplify.delete_undisplayable);
  EXPECT_FALSE(bounded.simplify.delete_undisplayable);
  EXPECT_EQ(bounded.simplify.bound_undisplayable_px, 2);
  EXPECT_EQ(settings_json(f.models[0].config)["keep_undisplayable"], "auto");
  // true and false stay booleans: batches that named one keep their hashes.
  EXPECT_EQ(settings_json(f.models[1].config)["keep_undisplayable"], false);
  EXPECT_EQ(settings_json(f.models[2].config)["keep_undisplayable"], true);
  for (const char* bad : {"keep_undisplayable: sometimes\n", "keep_undisplayable: [true]\n"})
    b.expect_refused(bad, "'keep_undisplayable' must be true, false or auto");
}

// tighten_to_limits: on by default in fidelity mode, off when asked, part of
// a fidelity model's settings hash only, and refused outside fidelity mode.
TEST(BatchConfig, TightenToLimitsIsOnByDefaultInFidelityMode) {
  BatchFolder b;
  ConfigFile f = b.models_with("tighten.yaml", {"tighten_to_limits: false", "simplify: paper"});
  ASSERT_EQ(f.models.size(), 3u);
  EXPECT_TRUE(lod_job(f.models[0].config).tighten_to_limits);
  EXPECT_FALSE(lod_job(f.models[1].config).tighten_to_limits);
  EXPECT_EQ(settings_json(f.models[0].config)["tighten_to_limits"], true);
  EXPECT_EQ(settings_json(f.models[1].config)["tighten_to_limits"], false);
  EXPECT_FALSE(settings_json(f.models[2].config).contains("tighten_to_limits"));  // paper's hashes stay
  b.expect_refused("simplify: paper\ntighten_to_limits: true\n", "'tighten_to_limits' applies only to 'simplify: fidelity'");
  b.expect_refused("tighten_to_limits: maybe\n", "'tighten_to_limits'");
}

// explain: off by default, on per model in any collapse mode, part of the
// settings hash only when on, and refused with cluster.
TEST(BatchConfig, ExplainCountsTheRefusalsOfTheCollapseModes) {
  BatchFolder b;
  ConfigFile f = b.models_with("explain.yaml", {"explain: true", "simplify: qem, target: 100, explain: true"});
  ASSERT_EQ(f.models.size(), 3u);
  EXPECT_FALSE(lod_job(f.models[0].config).simplify.explain_stop);
  EXPECT_TRUE(lod_job(f.models[1].config).simplify.explain_stop);
  EXPECT_TRUE(lod_job(f.models[2].config).simplify.explain_stop);
  EXPECT_FALSE(settings_json(f.models[0].config).contains("explain"));  // older hashes stay
  EXPECT_EQ(settings_json(f.models[1].config)["explain"], true);
  b.expect_refused("simplify: cluster\nexplain: true\n", "'explain' applies to the collapse modes");
  b.expect_refused("explain: sometimes\n", "'explain'");
}

TEST(BatchShards, ShardsPartitionTheListExactly) {
  for (size_t count : {0u, 1u, 5u, 17u})
    for (int n : {1, 2, 3, 8}) {
      std::multiset<size_t> all;
      for (int i = 0; i < n; ++i)
        for (size_t k : shard_indices(count, i, n)) all.insert(k);
      ASSERT_EQ(all.size(), count);
      for (size_t k = 0; k < count; ++k) EXPECT_EQ(all.count(k), 1u) << count << " " << n;
    }
  EXPECT_EQ(parse_shard("2/8"), std::make_pair(2, 8));
  for (const char* bad : {"8/8", "-1/2", "1", "a/b", "1/0", "1/2x", ""})
    EXPECT_NE(error_of([&] { parse_shard(bad); }).find("--shard"), std::string::npos) << bad;
}

TEST(BatchHash, HashesAreStableAndSeeOneByte) {
  test::TempDir d("hash");
  const std::string a = d.file("a.bin", "perclod"), b = d.file("b.bin", "perclOd");
  EXPECT_EQ(hash_file(a), hash_text("perclod"));
  EXPECT_EQ(hash_text(""), "fnv1a64:cbf29ce484222325");  // the FNV-1a 64 offset basis
  EXPECT_NE(hash_file(a), hash_file(b));
  EXPECT_NE(error_of([&] { hash_file(d / "none"); }).find("none: cannot open"), std::string::npos);
}

TEST(LodRanges, EachLodServesFromItsDistanceAndItsTileSwitchesThere) {
  // Pixel angle 1 mrad: a 2 cm displacement is under a pixel beyond 20 m.
  const double angle = 1e-3, fov = 2 * std::atan(0.5);  // view height = distance
  const int height = 1000;                             // px: 1 m of error is 1 px at 1,000 m
  auto r = lod_ranges({132, 56, 427}, {0.5, 0.02, 0.02}, angle, fov, height, 10.0);
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r[0].distance, 56);
  EXPECT_NEAR(r[0].switch_distance, 20, 1e-9);
  EXPECT_NEAR(r[0].from, 20, 1e-9);   // the finest: safe closer than it was made for
  EXPECT_NEAR(r[1].from, 132, 1e-9);  // the others from the distance they were made for
  EXPECT_NEAR(r[2].from, 427, 1e-9);  // even where d_th (20 m) is nearer
  EXPECT_EQ(r[0].to, r[1].from);
  EXPECT_EQ(r[1].to, r[2].from);
  EXPECT_TRUE(std::isinf(r[2].to));
  EXPECT_NEAR(r[0].screen_coverage, 10.0 / 132, 1e-12);
  EXPECT_EQ(r[2].screen_coverage, 0);
  // Tileset errors: the finest is a leaf (0); a coarser tile's error shows
  // kTilesetMaxScreenSpaceError pixels exactly at its own distance, so a
  // client refines it there, and no two nested tiles share an error.
  EXPECT_EQ(r[0].geometric_error, 0);
  for (size_t i = 1; i < r.size(); ++i) {
    const double sse = r[i].geometric_error * height / (r[i].from * 2 * std::tan(fov / 2));
    EXPECT_NEAR(sse, kTilesetMaxScreenSpaceError, 1e-9) << i;
    EXPECT_GT(r[i].geometric_error, r[i - 1].geometric_error) << i;
  }
  EXPECT_NEAR(r[1].geometric_error, 132 * 16.0 / 1000, 1e-12);
}

TEST(EnuFrame, AxesAreOrthonormalAndTheOriginIsOnTheEllipsoid) {
  auto m = enu_to_ecef(0, 0, 0);
  EXPECT_NEAR(m[12], 6378137.0, 1e-6);  // equator, Greenwich
  EXPECT_NEAR(m[8], 1, 1e-12);          // up = +X there
  EXPECT_NEAR(m[1], 1, 1e-12);          // east = +Y
  EXPECT_NEAR(m[6], 1, 1e-12);          // north = +Z
  auto p = enu_to_ecef(48.7665, 11.4258, 400);  // Ingolstadt
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double dot = 0;
      for (int k = 0; k < 3; ++k) dot += p[4 * i + k] * p[4 * j + k];
      EXPECT_NEAR(dot, i == j ? 1 : 0, 1e-12);
    }
  const double r = std::sqrt(p[12] * p[12] + p[13] * p[13] + p[14] * p[14]);
  EXPECT_GT(r, 6356752.0 + 400 - 1);
  EXPECT_LT(r, 6378137.0 + 400 + 1);
}

// A model tileset as run_model writes it, reduced to what the batch reads:
// a box of half-size h at x and the tileset's geometricError.
std::string model_tileset(double x, double h, double error) {
  nlohmann::json box = {x, 0, 0, h, 0, 0, 0, h, 0, 0, 0, h};
  nlohmann::json t = {{"asset", {{"version", "1.1"}}},
                      {"geometricError", error},
                      {"root", {{"boundingVolume", {{"box", box}}}, {"geometricError", error / 2}, {"refine", "REPLACE"}}}};
  return t.dump();
}

// The batch tileset's own error (that of drawing none of it) is never below
// its root's, whichever is larger: a model made for a far distance (its
// tileset's error above the batch's diameter) or the batch's extent.
// scripts/validate_exports.sh warns on a tileset below its root
// (TILESET_ERROR_BELOW_ROOT); a batch of one small building made for 12 km
// was: 93.7 against 113.1.
TEST(BatchTileset, ItsErrorIsTheRootsAndAtLeastEachModelsAndItsDiameter) {
  for (const bool far_distance : {true, false}) {
    test::TempDir out(far_distance ? "batchtileset-far" : "batchtileset-wide");
    const double error = far_distance ? 500 : 1;  // each model tileset's
    const double spread = far_distance ? 10 : 1000;  // between the two models, m
    fs::create_directories(out.path / "a");
    fs::create_directories(out.path / "b");
    fs::create_directories(out.path / ".c.partial-host-1");  // not complete: skipped
    out.file("a/a_tileset.json", model_tileset(0, 5, error));
    out.file("b/b_tileset.json", model_tileset(spread, 5, error));
    out.file(".c.partial-host-1/c_tileset.json", model_tileset(0, 5, 1e6));
    write_batch_tileset(out.path.string());
    std::ifstream in(batch_tileset_file(out.path.string()));
    ASSERT_TRUE(in) << "no batch tileset";
    const auto ts = nlohmann::json::parse(in);
    const auto& root = ts["root"];
    ASSERT_EQ(root["children"].size(), 2u);
    const double diameter = 2 * root["boundingVolume"]["sphere"][3].get<double>();
    EXPECT_GE(diameter, spread + 10);
    EXPECT_GE(ts["geometricError"].get<double>(), root["geometricError"].get<double>()) << far_distance;
    EXPECT_DOUBLE_EQ(root["geometricError"].get<double>(), std::max(error, diameter)) << far_distance;
    for (const auto& c : root["children"]) {
      EXPECT_EQ(c["geometricError"].get<double>(), error);  // the model tileset's own
      EXPECT_LE(c["geometricError"].get<double>(), root["geometricError"].get<double>());
      EXPECT_TRUE(fs::exists(out.path / c["content"]["uri"].get<std::string>()));
    }
    EXPECT_EQ(root["refine"], "ADD");
  }
}

// The GLB's JSON chunk.
nlohmann::json glb_json(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const uint32_t json_len = *reinterpret_cast<const uint32_t*>(bytes.data() + 12);
  return nlohmann::json::parse(bytes.substr(20, json_len));
}

// The floats of a float SCALAR or VEC3 accessor of a GLB (its binary chunk).
std::vector<float> glb_floats(const std::string& path, const nlohmann::json& g, int accessor) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const uint32_t json_len = *reinterpret_cast<const uint32_t*>(bytes.data() + 12);
  const size_t bin = 20 + json_len + 8;
  const auto& a = g["accessors"][accessor];
  const auto& v = g["bufferViews"][a["bufferView"].get<int>()];
  std::vector<float> f((a["type"] == "VEC3" ? 3 : 1) * a["count"].get<size_t>());
  std::memcpy(f.data(), bytes.data() + bin + v.value("byteOffset", size_t(0)), f.size() * sizeof(float));
  return f;
}

// Components are not nodes (a district would be thousands of draw calls) but
// feature ids: one node, one primitive per material colour, each vertex's
// component in _FEATURE_ID_0 (EXT_mesh_features), named by the mesh's extras.
TEST(GlbExport, ComponentsAreFeatureIdsOfOnePrimitivePerMaterialAndTheOffsetLoadsBack) {
  test::TempDir d("glbexport");
  Scene s = test::box();
  Scene two = test::box();
  for (size_t i = 0; i < two.positions.size(); i += 3) two.positions[i] += 3;
  const size_t base = s.vertex_count();
  s.positions.insert(s.positions.end(), two.positions.begin(), two.positions.end());
  for (uint32_t i : two.indices) s.indices.push_back(uint32_t(i + base));
  s.component.assign(24, 0);
  std::fill(s.component.begin() + 12, s.component.end(), 1);
  s.component_names = {"bldg_1/wall", "bldg_1/roof"};
  s.offset = {6780.5, 4035.25, 400};
  const std::string path = d / "two.glb";
  export_scene(s, path);
  const auto gltf = glb_json(path);
  ASSERT_EQ(gltf["nodes"].size(), 2u);
  EXPECT_EQ(gltf["nodes"][0]["translation"], (std::vector<double>{6780.5, 4035.25, 400}));  // exact, in double
  EXPECT_EQ(gltf["nodes"][0]["children"], (std::vector<int>{1}));
  ASSERT_EQ(gltf["meshes"].size(), 1u);
  ASSERT_EQ(gltf["meshes"][0]["primitives"].size(), 1u);  // one material
  EXPECT_EQ(gltf["meshes"][0]["extras"]["feature_names"], (std::vector<std::string>{"bldg_1/wall", "bldg_1/roof"}));
  EXPECT_EQ(gltf["extensionsUsed"], (std::vector<std::string>{"EXT_mesh_features"}));
  const auto& prim = gltf["meshes"][0]["primitives"][0];
  EXPECT_EQ(prim["extensions"]["EXT_mesh_features"]["featureIds"][0]["featureCount"], 2);
  EXPECT_EQ(prim["extensions"]["EXT_mesh_features"]["featureIds"][0]["attribute"], 0);
  // Each box's 24 crease vertices carry its component: the first box's 0, the second's 1.
  const std::vector<float> ids = glb_floats(path, gltf, prim["attributes"]["_FEATURE_ID_0"].get<int>());
  const std::vector<float> pos = glb_floats(path, gltf, prim["attributes"]["POSITION"].get<int>());
  ASSERT_EQ(ids.size(), 48u);
  for (size_t v = 0; v < ids.size(); ++v) EXPECT_EQ(ids[v], pos[3 * v] > 1.5f ? 1.f : 0.f) << v;
  // Back through assimp: the same triangles, the offset restored (assimp is
  // float: at UTM coordinates it would lose decimetres, here under a millimetre).
  Scene back = load_scene(path);
  EXPECT_EQ(back.triangle_count(), 24u);
  const Bounds bb = scene_bounds(back);
  for (int a = 0; a < 3; ++a) {
    const double lo = bb.lo[a] + back.offset[a];
    EXPECT_NEAR(lo, s.offset[a], 1e-3) << a;
  }
}

// Every primitive has its own POSITION and unit NORMALs (so viewers light
// it): a box's corners split at its 90 degree edges (24 vertices, normals
// along the axes), a finely faceted cylinder's stay shared (smooth), and
// materials of one colour are one glTF material.
TEST(GlbExport, PrimitivesHaveTheirOwnVerticesAndNormalsSplitAtCreases) {
  test::TempDir d("glbnormals");
  Scene box = test::box();
  box.materials = {{"wall_a", {0.8f, 0.8f, 0.8f}}, {"wall_b", {0.8f, 0.8f, 0.8f}}, {"roof", {0.9f, 0.1f, 0.1f}}};
  box.material.assign(box.triangle_count(), 0);
  for (size_t t = 0; t < box.triangle_count(); t += 2) box.material[t] = 1;  // same colour, another name
  box.material[0] = 2;
  export_scene(box, d / "box.glb");
  auto g = glb_json(d / "box.glb");
  EXPECT_EQ(g["materials"].size(), 2u);  // grey (wall_a and wall_b) and red
  for (const auto& m : g["materials"]) {  // rough dielectrics, not glTF's default metal
    EXPECT_EQ(m["pbrMetallicRoughness"]["metallicFactor"], 0.0);
    EXPECT_EQ(m["pbrMetallicRoughness"].value("roughnessFactor", 1.0), 1.0);
  }
  size_t vertices = 0;
  for (const auto& prim : g["meshes"][0]["primitives"]) {
    ASSERT_TRUE(prim["attributes"].contains("NORMAL"));
    const auto& pos = g["accessors"][prim["attributes"]["POSITION"].get<int>()];
    const auto& nrm = g["accessors"][prim["attributes"]["NORMAL"].get<int>()];
    EXPECT_EQ(pos["count"], nrm["count"]);
    EXPECT_TRUE(pos.contains("min") && pos.contains("max"));
    vertices += pos["count"].get<size_t>();
  }
  // Grey: 11 triangles on 6 faces, red: the other half of face 0. Each
  // face's corners are vertices of their own: 5 x 4 + 3 grey, 3 red.
  EXPECT_EQ(vertices, 5u * 4u + 3u + 3u);
  Scene back = load_scene(d / "box.glb");  // assimp reads the normals and the triangles back
  EXPECT_EQ(back.triangle_count(), box.triangle_count());

  // A cylinder of 64 facets (5.6 degrees apart) and no caps: smooth, so its
  // 128 vertices stay 128, and every normal is horizontal and of unit length.
  Scene cyl;
  const int n = 64;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * kPi * i / n;
    for (float z : {0.f, 3.f}) cyl.positions.insert(cyl.positions.end(), {float(std::cos(a)), float(std::sin(a)), z});
  }
  for (uint32_t i = 0; i < uint32_t(n); ++i) {
    const uint32_t j = (i + 1) % uint32_t(n);
    cyl.indices.insert(cyl.indices.end(), {2 * i, 2 * j, 2 * j + 1, 2 * i, 2 * j + 1, 2 * i + 1});
  }
  export_scene(cyl, d / "cyl.glb", ExportOptions{true});
  g = glb_json(d / "cyl.glb");
  ASSERT_EQ(g["meshes"][0]["primitives"].size(), 1u);
  EXPECT_EQ(g["accessors"][g["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<int>()]["count"], 128);
  const std::vector<float> nrm =
      glb_floats(d / "cyl.glb", g, g["meshes"][0]["primitives"][0]["attributes"]["NORMAL"].get<int>());
  for (size_t v = 0; v < nrm.size(); v += 3) {
    EXPECT_NEAR(std::hypot(nrm[v], nrm[v + 1], nrm[v + 2]), 1, 1e-5);
    EXPECT_NEAR(nrm[v + 1], 0, 1e-5);  // Z-up turned to glTF's Y: the axis is Y, normals horizontal
  }
  Scene smooth = load_scene(d / "cyl.glb");
  EXPECT_EQ(smooth.triangle_count(), 128u);
}

TEST(GlbExport, ZUpSourcesAreTurnedToGltfYUp) {
  test::TempDir d("glbzup");
  Scene s = test::box();
  for (size_t i = 2; i < s.positions.size(); i += 3) s.positions[i] *= 5;  // tall along Z
  s.offset = {10, 20, 30};
  export_scene(s, d / "z.glb", ExportOptions{true});
  std::ifstream in(d / "z.glb", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const uint32_t json_len = *reinterpret_cast<const uint32_t*>(bytes.data() + 12);
  auto gltf = nlohmann::json::parse(bytes.substr(20, json_len));
  EXPECT_EQ(gltf["nodes"][0]["translation"], (std::vector<double>{10, 30, -20}));
  const auto& acc = gltf["accessors"][0];
  EXPECT_NEAR(acc["max"][1].get<double>() - acc["min"][1].get<double>(), 5, 1e-6);  // height now along Y
  EXPECT_NEAR(acc["max"][2].get<double>() - acc["min"][2].get<double>(), 1, 1e-6);
}

TEST(GlbExport, AllLodsInOneFileWithMsftLod) {
  test::TempDir d("glblods");
  Scene fine = test::box(), coarse = test::box();
  coarse.indices.resize(6 * 3);  // fewer triangles
  const std::string path = d / "lods.glb";
  export_lods_glb({&fine, &coarse}, {"lod_56m", "lod_427m"}, {0.25, 0.0}, path);
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const uint32_t json_len = *reinterpret_cast<const uint32_t*>(bytes.data() + 12);
  auto gltf = nlohmann::json::parse(bytes.substr(20, json_len));
  EXPECT_EQ(gltf["extensionsUsed"], (std::vector<std::string>{"MSFT_lod", "EXT_mesh_features"}));
  const auto& lod0 = gltf["nodes"][1];
  EXPECT_EQ(lod0["name"], "lod_56m");
  EXPECT_EQ(lod0["extensions"]["MSFT_lod"]["ids"], (std::vector<int>{2}));
  EXPECT_EQ(lod0["extras"]["MSFT_screencoverage"], (std::vector<double>{0.25, 0.0}));
  EXPECT_EQ(gltf["scenes"][0]["nodes"], (std::vector<int>{0}));
  EXPECT_EQ(gltf["nodes"][0]["children"], (std::vector<int>{1}));  // the coarse LOD only through MSFT_lod
  EXPECT_EQ(gltf["meshes"].size(), 2u);
  EXPECT_NE(error_of([&] { export_lods_glb({&fine}, {"a", "b"}, {0}, path); }).find("one name"), std::string::npos);
}

TEST(GlbExport, AnEmptyLodIsARootNodeWithoutEmptyAccessors) {
  test::TempDir d("glbempty");
  Scene empty = test::box();
  empty.indices.clear();  // vertices left, no triangle
  empty.offset = {1, 2, 3};
  export_scene(empty, d / "empty.glb");
  std::ifstream in(d / "empty.glb", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const uint32_t json_len = *reinterpret_cast<const uint32_t*>(bytes.data() + 12);
  auto gltf = nlohmann::json::parse(bytes.substr(20, json_len));
  ASSERT_EQ(gltf["nodes"].size(), 1u);
  EXPECT_EQ(gltf["nodes"][0]["translation"], (std::vector<double>{1, 2, 3}));
  EXPECT_FALSE(gltf.contains("accessors") && !gltf["accessors"].empty());
  EXPECT_FALSE(gltf.contains("buffers") && !gltf["buffers"].empty());
  // assimp reads it: perclod's loader then refuses it for what it is, empty.
  EXPECT_NE(error_of([&] { load_scene(d / "empty.glb"); }).find("no triangles (empty model)"), std::string::npos);
}

// An OBJ LOD of a model whose file gave no colours reads back without
// colours, so it renders in its components' colours as the original does,
// while a colour the source gave survives the round trip.
TEST(ObjExport, MaterialsKeepTheirColourOrTheirLackOfOne) {
  test::TempDir d("objcolours");
  Scene plain = test::box();
  export_scene(plain, d / "plain.obj");
  Scene back = load_scene(d / "plain.obj");
  ASSERT_EQ(back.triangle_count(), plain.triangle_count());
  for (size_t t = 0; t < back.triangle_count(); ++t) {
    const Material* m = back.material_of(t);
    EXPECT_TRUE(m == nullptr || !m->has_color) << t;
  }
  Scene red = test::box();
  red.materials = {{"roof", {0.9f, 0.1f, 0.1f}, true}};
  red.material.assign(red.triangle_count(), 0);
  export_scene(red, d / "red.obj");
  back = load_scene(d / "red.obj");
  const Material* m = back.material_of(0);
  ASSERT_NE(m, nullptr);
  EXPECT_TRUE(m->has_color);
  EXPECT_FLOAT_EQ(m->color[0], 0.9f);
  EXPECT_FLOAT_EQ(m->color[1], 0.1f);
}
