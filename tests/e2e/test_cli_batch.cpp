// `perclod run` over a batch: failures reported and survived, reruns skipped,
// shards that partition the list, and the manifest, tileset and GLBs a viewer loads.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <map>
#include <set>
#include <sstream>

#include "cli_util.h"
#include "perclod/config.h"
#include "perclod/load.h"
#include "perclod/run_model.h"

using perclod::test::run_cli;
namespace fs = std::filesystem;

namespace {

// A 12 x 8 x 10 m block with a slab and a chimney: three boxes, three groups
// named `<name>/...`; its vertices follow `first_vertex` others in the file.
std::string building_obj(double dx, const std::string& name = "house", int first_vertex = 0) {
  std::string s;
  int base = first_vertex;
  auto box = [&](const char* name, double x0, double y0, double z0, double x1, double y1, double z1) {
    s += std::string("g ") + name + "\n";
    for (int k = 0; k < 8; ++k)
      s += "v " + std::to_string((k & 1 ? x1 : x0) + dx) + " " + std::to_string(k & 2 ? y1 : y0) + " " +
           std::to_string(k & 4 ? z1 : z0) + "\n";
    const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (auto& f : q)
      s += "f " + std::to_string(base + f[0] + 1) + " " + std::to_string(base + f[1] + 1) + " " +
           std::to_string(base + f[2] + 1) + " " + std::to_string(base + f[3] + 1) + "\n";
    base += 8;
  };
  box((name + "/body").c_str(), 0, 0, 0, 12, 8, 10);
  box((name + "/slab").c_str(), -0.5, -0.5, 10, 12.5, 8.5, 10.3);
  box((name + "/chimney").c_str(), 2, 2, 10.3, 2.6, 2.6, 11.5);
  return s;
}

// Every batch config here is written beside BatchDir's small-display.yaml.
constexpr const char* kRunSettings =
    "distances: [56]\nviews: facades\nsamples: 1\njudge_views: none\ndisplay: small-display.yaml\n";

struct BatchDir {
  fs::path root;
  explicit BatchDir(const std::string& name) {
    root = perclod::test::fresh_dir("batch-" + name);
    fs::create_directories(root / "models");
    std::ofstream(root / "models" / "alpha.obj") << building_obj(0);
    std::ofstream(root / "models" / "beta.obj") << building_obj(100);
    std::ofstream(root / "models" / "broken.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n";
    // A quarter of the paper display's resolution at its size and distance:
    // a sixteenth of the pixels to render, perceive and trace, which is what
    // these runs spend their time on (they test the batch, not the labels).
    std::ofstream(root / "small-display.yaml")
        << "name: test-320\nwidth: 320\nheight: 256\ndpi: 21.5675\nviewer_distance_m: 0.5\n";
    std::ofstream(root / "batch.yaml") << "out: " << (root / "out").string() << "\n" << kRunSettings
                                       << "models:\n  - models/alpha.obj\n  - models/broken.obj\n"
                                       << "  - {model: models/beta.obj, up: z, crs_origin: {lat: 48.77, lon: 11.43, height: 370}}\n";
  }
  ~BatchDir() { fs::remove_all(root); }
  std::string config() const { return (root / "batch.yaml").string(); }
  fs::path out() const { return root / "out"; }
};

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

std::map<std::string, std::string> statuses(const nlohmann::json& summary) {
  std::map<std::string, std::string> r;
  for (const auto& m : summary["models"]) r[m["name"]] = m["status"];
  return r;
}

// Walks a tileset: every tile's required fields, errors that shrink with
// depth, content files that exist. Returns the tiles' depth count.
int check_tile(const nlohmann::json& tile, const fs::path& dir, double parent_error, int depth) {
  EXPECT_TRUE(tile.contains("boundingVolume"));
  EXPECT_TRUE(tile["boundingVolume"].contains("box") || tile["boundingVolume"].contains("sphere"));
  const double e = tile.at("geometricError").get<double>();
  if (depth == 0) EXPECT_LE(e, parent_error);
  else EXPECT_LT(e, parent_error) << "depth " << depth << ": nested tiles with equal errors hide a LOD";
  if (tile.contains("content")) {
    const std::string uri = tile["content"]["uri"];
    EXPECT_TRUE(fs::exists(dir / uri)) << uri;
  }
  int deepest = depth;
  if (tile.contains("children"))
    for (const auto& c : tile["children"]) deepest = std::max(deepest, check_tile(c, dir, e, depth + 1));
  else
    EXPECT_EQ(e, 0) << "a leaf LOD is the finest: nothing to refine to";
  return deepest;
}

// The manifest's checksums name every file of the model's outputs in `dir`
// (all but the manifest and hidden files) with that file's hash.
void expect_checksums_match(const nlohmann::json& m, const fs::path& dir) {
  std::set<std::string> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n[0] != '.' && n.find("_manifest.json") == std::string::npos) files.insert(n);
  }
  ASSERT_TRUE(m.contains("checksums"));
  std::set<std::string> summed;
  for (const auto& [name, hash] : m["checksums"].items()) {
    summed.insert(name);
    EXPECT_EQ(hash.get<std::string>(), perclod::hash_file((dir / name).string())) << name;
  }
  EXPECT_EQ(summed, files);
}

}  // namespace

TEST(CliBatch, AFailedModelIsReportedTheOthersCompleteAndARerunSkipsThem) {
  BatchDir b("fail");
  auto r = run_cli("run " + b.config() + " --json");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("1 of 3 models failed (broken)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("broken.obj"), std::string::npos) << r.err;  // the file and what is wrong
  EXPECT_NE(r.err.find("[2/3 broken] FAILED"), std::string::npos) << r.err;
  auto s = nlohmann::json::parse(r.out);
  EXPECT_EQ(statuses(s), (std::map<std::string, std::string>{{"alpha", "done"}, {"beta", "done"}, {"broken", "failed"}}));
  EXPECT_EQ(s["done"], 2);
  EXPECT_EQ(s["failed"], 1);
  EXPECT_TRUE(fs::exists(b.out() / "alpha" / "alpha_manifest.json"));
  EXPECT_TRUE(fs::exists(b.out() / "beta" / "beta_manifest.json"));
  EXPECT_FALSE(fs::exists(b.out() / "broken"));
  for (const auto& e : fs::directory_iterator(b.out()))
    EXPECT_EQ(e.path().filename().string().find(".partial"), std::string::npos) << e.path();
  // Paths in the report are relative to the model's folder (no partial folder).
  const auto report = read_json(b.out() / "alpha" / "alpha_report.json");
  EXPECT_EQ(report["lods"][0]["lod_file"], "alpha_lod_56m.obj");

  const auto before = fs::last_write_time(b.out() / "alpha" / "alpha_manifest.json");
  r = run_cli("run " + b.config() + " --json");
  EXPECT_EQ(r.exit_code, 1);
  s = nlohmann::json::parse(r.out);
  EXPECT_EQ(statuses(s), (std::map<std::string, std::string>{{"alpha", "skipped"}, {"beta", "skipped"}, {"broken", "failed"}}));
  EXPECT_EQ(fs::last_write_time(b.out() / "alpha" / "alpha_manifest.json"), before);

  // A changed input is redone; --force redoes everything.
  std::ofstream(b.root / "models" / "alpha.obj", std::ios::app) << "# edited\n";
  r = run_cli("run " + b.config() + " --json");
  s = nlohmann::json::parse(r.out);
  EXPECT_EQ(statuses(s)["alpha"], "done");
  EXPECT_EQ(statuses(s)["beta"], "skipped");
  r = run_cli("run " + b.config() + " --json --force");
  s = nlohmann::json::parse(r.out);
  EXPECT_EQ(statuses(s)["beta"], "done");
}

TEST(CliBatch, ShardsPartitionTheModels) {
  BatchDir b("shard");
  std::multiset<std::string> seen;
  for (const char* shard : {"0/2", "1/2"}) {
    auto r = run_cli("run " + b.config() + " --json --shard " + shard);
    auto s = nlohmann::json::parse(r.out);
    EXPECT_EQ(s["shard"], shard);
    for (const auto& m : s["models"]) seen.insert(m["name"].get<std::string>());
    EXPECT_TRUE(fs::exists(b.out() / (std::string("batch_") + shard[0] + "_of_2.json")));
  }
  EXPECT_EQ(seen, (std::multiset<std::string>{"alpha", "beta", "broken"}));
  auto r = run_cli("run " + b.config() + " --shard 2/2");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("0 <= i < n"), std::string::npos) << r.err;
}

TEST(CliBatch, ManifestTilesetAndGlbsValidate) {
  BatchDir b("export");
  auto r = run_cli("run " + b.config());
  ASSERT_EQ(r.exit_code, 1) << r.err;  // broken.obj
  for (const std::string name : {"alpha", "beta"}) {
    const fs::path dir = b.out() / name;
    const auto m = read_json(dir / (name + "_manifest.json"));
    EXPECT_EQ(m["schema"], "perclod-manifest/1");
    EXPECT_TRUE(m["complete"].get<bool>());
    EXPECT_EQ(m["model"]["hash"].get<std::string>().substr(0, 8), "fnv1a64:");
    EXPECT_EQ(m["config"]["hash"].get<std::string>().substr(0, 8), "fnv1a64:");
    EXPECT_EQ(m["model"]["triangles"], 36);
    ASSERT_EQ(m["lods"].size(), 1u);
    const auto& lod = m["lods"][0];
    EXPECT_EQ(lod["distance"], 56);
    EXPECT_LE(lod["serves"]["from"].get<double>(), 56);
    EXPECT_TRUE(lod["serves"]["to"].is_null());  // the last LOD serves every farther distance
    const auto& t = lod["triangles"];
    EXPECT_EQ(t["total"].get<int>(),
              t["perceptible"].get<int>() + t["imperceptible"].get<int>() + t["undisplayable"].get<int>());
    EXPECT_EQ(lod["fidelity"]["views"].size(), 4u);  // the four facades (judge_views: none)
    for (const auto& v : lod["fidelity"]["views"])  // both perceptual figures, against floors measured
      EXPECT_TRUE(v.contains("visible_ratio") && v.contains("visible_local_ratio")) << v;
    for (const auto& key : {"report", "lods_glb", "tileset"})
      EXPECT_TRUE(fs::exists(dir / m["files"][key].get<std::string>())) << key;
    EXPECT_TRUE(fs::exists(dir / lod["file"].get<std::string>()));
    // The GLB loads back through assimp with the LOD's triangles and offset.
    perclod::Scene glb = perclod::load_scene((dir / lod["glb"].get<std::string>()).string());
    EXPECT_EQ(glb.triangle_count(), t["total"].get<size_t>());
    const auto ts = read_json(dir / m["files"]["tileset"].get<std::string>());
    EXPECT_EQ(ts["asset"]["version"], "1.1");
    EXPECT_EQ(ts["asset"]["extras"]["perclod"]["maximum_screen_space_error"], 16);
    EXPECT_GE(ts["geometricError"].get<double>(), ts["root"]["geometricError"].get<double>());
    check_tile(ts["root"], dir, ts["geometricError"].get<double>(), 0);
    // Hashes of the files as published, the report rewritten with relative paths included.
    expect_checksums_match(m, dir);
    if (name == "beta") {
      EXPECT_EQ(m["model"]["up"], "z");
      EXPECT_EQ(ts["root"]["transform"].size(), 16u);  // crs_origin: local ENU frame
      // Z-up source: glTF Y-up; the file's bounds (x 100..112.5) come back with the offset.
      const perclod::Bounds bb = perclod::scene_bounds(glb);
      EXPECT_NEAR(bb.lo[0] + glb.offset[0], 99.5, 1e-3);
      EXPECT_NEAR(bb.hi[1] - bb.lo[1], 11.5, 1e-3);  // the height (source Z) is glTF's Y
    } else {
      EXPECT_FALSE(ts["root"].contains("transform"));
      const perclod::Bounds bb = perclod::scene_bounds(glb);
      EXPECT_NEAR(bb.lo[0] + glb.offset[0], -0.5, 1e-3);
    }
  }
  const auto batch = read_json(b.out() / "tileset.json");
  EXPECT_EQ(batch["asset"]["version"], "1.1");
  ASSERT_EQ(batch["root"]["children"].size(), 2u);
  for (const auto& c : batch["root"]["children"])
    EXPECT_TRUE(fs::exists(b.out() / c["content"]["uri"].get<std::string>())) << c;
}

TEST(CliBatch, OneModelConfigsWriteTheManifestBesideTheLods) {
  BatchDir b("single");
  std::ofstream(b.root / "one.yaml") << "model: models/alpha.obj\nout: " << (b.root / "one").string()
                                     << "\ndistances: [56, 427]\nviews: facades\nsamples: 1\njudge_views: none\n"
                                     << "display: small-display.yaml\n";
  auto r = run_cli("run " + (b.root / "one.yaml").string() + " --shard 0/2");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("apply to a batch"), std::string::npos) << r.err;
  r = run_cli("run " + (b.root / "one.yaml").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto m = read_json(b.root / "one" / "alpha_manifest.json");
  ASSERT_EQ(m["lods"].size(), 2u);
  EXPECT_EQ(m["lods"][0]["serves"]["to"], m["lods"][1]["serves"]["from"]);
  EXPECT_TRUE(fs::exists(b.root / "one" / "alpha_lod_427m.glb"));
  EXPECT_TRUE(fs::exists(b.root / "one" / "alpha_lods.glb"));
  expect_checksums_match(m, b.root / "one");
}

// `perclod run` of b's models/two.obj at 56 m, Z up, one sample, the small
// display and `settings`, into b.root / name: the LOD's report entry.
nlohmann::json run_two(const BatchDir& b, const std::string& name, const std::string& settings) {
  std::ofstream(b.root / (name + ".yaml")) << "model: models/two.obj\nout: " << (b.root / name).string()
                                           << "\nup: z\ndistances: [56]\nsamples: 1\ndisplay: small-display.yaml\n"
                                           << settings;
  auto r = run_cli("run " + (b.root / (name + ".yaml")).string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return read_json(b.root / name / "two_report.json")["lods"][0];
}

// The faces of `building` (OBJ groups `<building>/...`) in an OBJ file, a
// line each, with their corners' vertex lines in place of indices.
std::string faces_of(const fs::path& obj, const std::string& building) {
  std::ifstream f(obj);
  std::string line, group, faces;
  std::vector<std::string> v;
  while (std::getline(f, line)) {
    if (line.rfind("v ", 0) == 0) v.push_back(line);
    else if (line.rfind("g ", 0) == 0) group = line.substr(2, line.find('/') - 2);
    else if (line.rfind("f ", 0) == 0 && group == building) {
      std::istringstream in(line.substr(2));
      for (std::string c; in >> c;) faces += v[std::stoul(c) - 1] + ";";
      faces += "\n";
    }
  }
  return faces;
}

// A dome of `rings` x `segments` quads (radius r, centre x, y, z) as an OBJ
// group named `name` whose vertices follow `first_vertex` others.
std::string dome_obj(const std::string& name, double x, double y, double z, double r, int rings, int segments,
                     int first_vertex) {
  std::string s = "g " + name + "\n";
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double t = 0.5 * M_PI * i / rings, p = 2 * M_PI * j / segments;
      s += "v " + std::to_string(x + r * std::sin(t) * std::cos(p)) + " " + std::to_string(y + r * std::sin(t) * std::sin(p)) +
           " " + std::to_string(z + r * std::cos(t)) + "\n";
    }
  auto at = [&](int i, int j) { return std::to_string(first_vertex + 1 + i * segments + (j % segments)); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j)
      s += "f " + at(i, j) + " " + at(i + 1, j) + " " + at(i + 1, j + 1) + " " + at(i, j + 1) + "\n";
  return s;
}

// models/two.obj: house a (three boxes) and house b with a finely made dome.
void write_houses_a_and_domed_b(const BatchDir& b) {
  std::ofstream(b.root / "models" / "two.obj")
      << building_obj(0, "a") + building_obj(30, "b", 24) + dome_obj("b/dome", 36, 4, 10.3, 3.5, 12, 32, 48);
}

// run_two without debug images.
nlohmann::json run_two_quiet(const BatchDir& b, const std::string& name, const std::string& settings) {
  return run_two(b, name, "debug_images: false\n" + settings);
}

// Per-building tightening: house b carries a finely made dome whose LOD at
// the asked bounds differs from it; with max_visible at half b's worst
// visible ratio, only b is made again at tighter bounds, until within, and
// a keeps its LOD (a plain house, unchanged either way).
TEST(CliBatch, OnlyTheBuildingsOverTheLimitsAreTightened) {
  BatchDir b("tighten-buildings");
  write_houses_a_and_domed_b(b);
  auto run = [&](const std::string& name, const std::string& settings) { return run_two_quiet(b, name, settings); };
  const auto asked = run("asked", "");
  double worst_b = 0;
  for (const auto& v : asked["lod_vs_original"])
    if (v["building"] == "b") worst_b = std::max(worst_b, v["visible_ratio"].get<double>());
  ASSERT_GT(worst_b, 0.0);
  std::ostringstream limit;
  limit << "max_visible: " << worst_b / 2 << "\n";
  const auto tight = run("tight", limit.str());
  EXPECT_EQ(tight["judged_alone"]["tightened"], 1);
  EXPECT_EQ(tight["judged_alone"]["within_limits"], 2);
  ASSERT_GE(tight["tighten_to_limits"].size(), 2u);
  EXPECT_FALSE(tight["tighten_to_limits"][0]["met"].get<bool>());
  EXPECT_TRUE(tight["tighten_to_limits"].back()["met"].get<bool>());
  EXPECT_GT(tight["simplify"]["triangles_after"]["total"].get<int>(), asked["simplify"]["triangles_after"]["total"].get<int>());
  // House a's faces in both LODs: the same lines.
  const std::string a_asked = faces_of(b.root / "asked" / "two_lod_56m.obj", "a");
  EXPECT_FALSE(a_asked.empty());
  EXPECT_TRUE(faces_of(b.root / "tight" / "two_lod_56m.obj", "a") == a_asked);
  EXPECT_TRUE(faces_of(b.root / "tight" / "two_lod_56m.obj", "b") != faces_of(b.root / "asked" / "two_lod_56m.obj", "b"));
  // From the default 8 px the tries halve e_I (while above 0.5 px) and
  // never loosen e_P; house b as written is house b of a run of the whole
  // file at the bounds of the try that met the limits (tightened_bounds).
  const auto& tries = tight["tighten_to_limits"];
  EXPECT_EQ(tries[0]["e_imperceptible"].get<double>(), perclod::kDefaultBoundImperceptiblePx);
  for (size_t i = 1; i < tries.size(); ++i) {
    const double e = tries[i]["e_imperceptible"].get<double>(), before = tries[i - 1]["e_imperceptible"].get<double>();
    if (before > 0.5) {
      EXPECT_EQ(e, std::max(0.5, before / 2)) << tries;
    }
    EXPECT_EQ(tries[i]["e_perceptible"].get<double>(), std::min(0.5, e)) << tries[i];
  }
  // (Here the dome's LOD is the same at every halving, held by e_P, and the
  // first sub-pixel step, 0.25 px for both, meets the limit.)
  const double kept_e = tries.back()["e_imperceptible"].get<double>();
  ASSERT_EQ(tries.back()["undisplayable"], "deleted") << tries;
  std::ostringstream at_kept;
  at_kept << "tighten_to_limits: false\ne_imperceptible: " << kept_e << "\ne_perceptible: " << std::min(0.5, kept_e)
          << "\n";
  run("at_kept", at_kept.str());
  EXPECT_TRUE(faces_of(b.root / "at_kept" / "two_lod_56m.obj", "b") == faces_of(b.root / "tight" / "two_lod_56m.obj", "b"));
}

// fidelity_target with buildings judged alone: each house takes the
// loosest bounds within the target in its own views. House a (three boxes)
// and house b (with a finely made dome) end at different bounds; the LOD
// holds no more triangles than the asked bounds' and no building is over
// the target; b's faces are those of a run at b's bounds for the whole file.
TEST(CliBatch, TheFidelitySearchFindsEachBuildingItsOwnBounds) {
  BatchDir b("search-buildings");
  write_houses_a_and_domed_b(b);
  auto run = [&](const std::string& name, const std::string& settings) { return run_two_quiet(b, name, settings); };
  const auto asked = run("asked", "tighten_to_limits: false\n");
  const auto searched = run("searched", "fidelity_target: {max_visible: 0.3}\n");
  ASSERT_TRUE(searched["judged_alone"].contains("searched")) << searched["judged_alone"].dump();
  const auto& steps = searched["judged_alone"]["searched"]["steps"];
  int buildings = 0;
  for (const auto& s : steps) buildings += s["buildings"].get<int>();
  EXPECT_EQ(buildings, 2);
  ASSERT_EQ(steps.size(), 2u) << steps.dump();  // two bounds, loosest first
  // Each house as a run of the whole file at its bounds makes it (e_P as
  // fidelity_bounds sets it: a quarter of e_I, at least the asked 0.5 px).
  const std::string searched_obj = (b.root / "searched" / "two_lod_56m.obj").string();
  std::set<std::string> houses;
  for (const auto& s : steps) {
    const double e = s["e_imperceptible"].get<double>();
    std::ostringstream bounds;
    bounds << "tighten_to_limits: false\ne_imperceptible: " << e << "\ne_perceptible: " << std::max(0.5, e / 4) << "\n";
    const std::string name = "at" + std::to_string(int(e * 8));
    run(name, bounds.str());
    const fs::path at = b.root / name / "two_lod_56m.obj";
    for (const std::string house : {"a", "b"})
      if (faces_of(at, house) == faces_of(searched_obj, house)) houses.insert(house + "@" + name);
  }
  // Each house matched at one of the two bounds; the domed house b at one
  // only (the three boxes of a may come out the same at both).
  std::map<std::string, int> matches;
  for (const std::string& h : houses) matches[h.substr(0, 1)]++;
  EXPECT_EQ(matches.size(), 2u) << ::testing::PrintToString(houses);
  EXPECT_EQ(matches["b"], 1) << ::testing::PrintToString(houses);
  // The report page says which bounds the buildings took.
  std::ifstream page(b.root / "searched" / "two_report.html");
  const std::string html((std::istreambuf_iterator<char>(page)), {});
  EXPECT_NE(html.find("<tr><td>bounds per building</td>"), std::string::npos);
  // A house within the target only below the loosest step is tried once
  // more midway between its step and the one that failed it (midway_step).
  int midway = 0;
  for (const auto& t : searched["fidelity_search"]) {
    const double e = t["e_imperceptible"].get<double>();
    midway += std::fabs(std::log2(e) - std::round(std::log2(e))) > 0.4;  // 2^(k + 1/2)
  }
  EXPECT_GE(midway, 1) << searched["fidelity_search"].dump();
  EXPECT_EQ(searched["judged_alone"]["searched"]["unmet"], 0);
  EXPECT_EQ(searched["judged_alone"]["within_limits"], 2);
  for (const auto& v : searched["lod_vs_original"]) EXPECT_LE(v["visible_ratio"].get<double>(), 1.0) << v["view"];
  EXPECT_LE(searched["simplify"]["triangles_after"]["total"].get<int>(),
            asked["simplify"]["triangles_after"]["total"].get<int>());
}

// A file of two houses, each labelled from its own views of it alone (the
// default): the whole-model views count nothing, are drawn only for the
// pictures a run writes, and each house's LOD is judged alone from the
// held-out views framed on it (with judge_buildings_alone: false from the
// held-out views framed on the file), or with judge_views: none from the
// labelling views framed on the whole file. House a, three boxes, is its
// own LOD and needs no view; b carries a finely made dome.
TEST(CliBatch, TwoHousesAreLabelledFromTheirOwnViewsAndJudgedFromHeldOutViews) {
  BatchDir b("two-houses");
  write_houses_a_and_domed_b(b);
  auto run = [&](const std::string& name, const std::string& settings) {
    return run_two(b, name, "views: facades\n" + settings);
  };
  const auto none = run("none", "judge_views: none\ndebug_images: false\n");
  const auto held = run("held", "");  // held-out views, debug images
  for (const auto* lod : {&none, &held}) {
    EXPECT_EQ((*lod)["model_views_counted"], false);
    ASSERT_EQ((*lod)["per_building"].size(), 2u);
    for (const auto& e : (*lod)["per_building"]) EXPECT_EQ(e["views"], 4);
  }
  EXPECT_TRUE(none["views"].empty());
  ASSERT_GE(none["lod_vs_original"].size(), 4u);
  for (const auto& v : none["lod_vs_original"]) EXPECT_EQ(v["set"], "labelling") << v["view"];
  // Drawn for their pictures: their renders and markings are written, and
  // the labels are the same bytes.
  EXPECT_GE(held["views"].size(), 4u);
  EXPECT_TRUE(fs::exists(b.root / "held" / "two_+x_56m_marking.png"));
  EXPECT_TRUE(fs::exists(b.root / "held" / "two_+x_56m.png"));
  // Judged house by house: b from 9 held-out views, a unchanged without
  // any; the report keeps each judged house's worst view (and any over a
  // limit).
  EXPECT_EQ(held["judged_alone"]["buildings"], 2);
  EXPECT_EQ(held["judged_alone"]["unchanged"], 1);
  EXPECT_EQ(held["judged_alone"]["views"], 9);
  EXPECT_EQ(held["judged_alone"]["within_limits"], 2);
  ASSERT_EQ(held["lod_vs_original"].size(), 1u);
  const auto& worst = held["lod_vs_original"][0];
  EXPECT_EQ(worst["set"], "held_out") << worst["view"];
  EXPECT_EQ(worst["building"], "b");
  EXPECT_EQ(worst["view"].get<std::string>().rfind("b/az", 0), 0u) << worst["view"];
  const auto model = run("model", "judge_buildings_alone: false\ndebug_images: false\n");
  EXPECT_FALSE(model.contains("judged_alone"));
  ASSERT_GE(model["lod_vs_original"].size(), 9u);
  for (const auto& v : model["lod_vs_original"]) {
    EXPECT_EQ(v["set"], "held_out") << v["view"];
    EXPECT_FALSE(v.contains("building")) << v["view"];
  }
  auto bytes = [](const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  EXPECT_EQ(bytes(b.root / "none" / "two_labels_56m.txt"), bytes(b.root / "held" / "two_labels_56m.txt"));
  // The report page says where the labels came from, and lists no whole-
  // model view as a labelling one when none was drawn.
  const std::string page = bytes(b.root / "none" / "two_report.html");
  EXPECT_NE(page.find("Each of the 2 buildings was labelled from its own views of it alone (8 views in all)"),
            std::string::npos);
  EXPECT_EQ(page.find("labelling view</th>"), std::string::npos);
  EXPECT_NE(bytes(b.root / "held" / "two_report.html").find("listed for their pictures only"), std::string::npos);
}

TEST(CliBatch, CityJsonModelsTakeTheirLodFromTheConfig) {
  BatchDir b("cityjson");
  const std::string fixture = PERCLOD_SOURCE_DIR "/tests/pipeline/fixtures/bldg_4018215.city.json";
  std::ofstream(b.root / "city.yaml") << "out: " << (b.root / "cj").string() << "\n"
                                      << kRunSettings << "up: z\n"
                                      << "models:\n  - {model: " << fixture << ", cityjson_lod: \"2\"}\n"
                                      << "  - {model: " << fixture << ", cityjson_lod: \"3\"}\n";
  auto r = run_cli("run " + (b.root / "city.yaml").string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto s = nlohmann::json::parse(r.out);
  ASSERT_EQ(s["models"].size(), 2u);
  // The same file twice: the folder's name first, then a number, tell them apart.
  // CityJSON's "name.city.json" names its outputs "name", not "name.city".
  EXPECT_EQ(s["models"][0]["name"], "fixtures_bldg_4018215");
  EXPECT_EQ(s["models"][1]["name"], "fixtures_bldg_4018215_2");
  const auto lod2 = read_json(b.root / "cj" / "fixtures_bldg_4018215" / "bldg_4018215_manifest.json");
  const auto lod3 = read_json(b.root / "cj" / "fixtures_bldg_4018215_2" / "bldg_4018215_manifest.json");
  EXPECT_EQ(lod2["model"]["triangles"], 12);     // the box of the fixture's lod 2
  EXPECT_EQ(lod3["model"]["triangles"], 12456);  // the converted LOD3 building
  EXPECT_EQ(lod2["config"]["settings"]["cityjson_lod"], "2");
  EXPECT_NE(lod2["config"]["hash"], lod3["config"]["hash"]);
  // Real UTM coordinates through the file's transform, in double.
  EXPECT_NEAR(lod3["model"]["offset"][0].get<double>(), 678117.251, 2e-3);
}

TEST(CliBatch, ModelsInParallelGiveTheSameOutputsAndTheMemoryBudgetHoldsThemBack) {
  BatchDir b("jobs");
  std::ofstream(b.root / "seq.yaml") << "out: " << (b.root / "seq").string() << "\n"
                                     << kRunSettings
                                     << "models:\n  - models/alpha.obj\n  - models/broken.obj\n"
                                     << "  - {model: models/beta.obj, up: z}\n";
  std::ofstream(b.root / "par.yaml") << "out: " << (b.root / "par").string() << "\njobs: 2\n"
                                     << kRunSettings
                                     << "models:\n  - models/alpha.obj\n  - models/broken.obj\n"
                                     << "  - {model: models/beta.obj, up: z}\n";
  auto seq = run_cli("run " + (b.root / "seq.yaml").string());
  auto par = run_cli("run " + (b.root / "par.yaml").string());
  EXPECT_EQ(seq.exit_code, 1);
  EXPECT_EQ(par.exit_code, 1);
  // Two at a time: broken.obj starts before alpha is done.
  const size_t alpha_done = par.err.find("[1/3 alpha] done"), broken_start = par.err.find("[2/3 broken] start");
  ASSERT_NE(alpha_done, std::string::npos) << par.err;
  ASSERT_NE(broken_start, std::string::npos) << par.err;
  EXPECT_LT(broken_start, alpha_done) << par.err;
  for (const std::string name : {"alpha", "beta"})
    for (const std::string file : {"_labels_56m.txt", "_lod_56m.obj", "_lod_56m.glb"}) {
      std::ifstream a(b.root / "seq" / name / (name + file)), p(b.root / "par" / name / (name + file));
      const std::string sa((std::istreambuf_iterator<char>(a)), {}), sp((std::istreambuf_iterator<char>(p)), {});
      EXPECT_FALSE(sa.empty()) << name + file;
      EXPECT_EQ(sa, sp) << name + file;
    }
  // A budget that fits one model's estimate (about 500 MiB) but not two runs one at a time.
  par = run_cli("run " + (b.root / "par.yaml").string() + " --force --memory-budget-mb 700");
  EXPECT_LT(par.err.find("[1/3 alpha] done"), par.err.find("[2/3 broken] start")) << par.err;
}

// The configs users copy load as they say (the batch one names ../shared/data).
TEST(ShippedConfigs, LoadWithTheModelsAndSettingsTheyDescribe) {
  const std::string dir = PERCLOD_SOURCE_DIR "/configs/";
  perclod::ConfigFile demo = perclod::load_config_file(dir + "demo.yaml");
  EXPECT_FALSE(demo.batch);
  EXPECT_EQ(demo.models.front().config.simplify, "fidelity");
  EXPECT_EQ(perclod::load_config_file(dir + "paper.yaml").models.front().config.simplify, "paper");
  perclod::ConfigFile city = perclod::load_config_file(dir + "city-batch.yaml");
  ASSERT_TRUE(city.batch);
  std::vector<std::string> names;
  for (const auto& m : city.models) names.push_back(m.name);
  EXPECT_EQ(names, (std::vector<std::string>{"han_ministry", "sibenik", "sponza", "bldg_4018215",
                                              "ingolstadt_lod3_all53"}));
  for (const auto& m : city.models) {
    const bool ingolstadt = m.name.rfind("ingolstadt", 0) == 0 || m.name == "bldg_4018215";
    EXPECT_EQ(m.config.up, ingolstadt ? perclod::UpAxis::Z : perclod::UpAxis::Y) << m.name;
    EXPECT_EQ(m.config.crs_origin, ingolstadt) << m.name;
  }
}
