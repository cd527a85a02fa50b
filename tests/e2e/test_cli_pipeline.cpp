// label and run through the CLI, on the demo building.
#include <algorithm>
#include <gtest/gtest.h>

#include <cmath>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <regex>

#include "cli_util.h"
#include "perclod/labels_io.h"
#include "perclod/load.h"
#include "perclod/fidelity_search.h"
#include "perclod/judge.h"
#include "perclod/undisplayable.h"

using perclod::test::run_cli;
namespace fs = std::filesystem;

using perclod::test::fresh_dir;
using perclod::test::kBuilding;

TEST(CliPipeline, LabelWritesLabelsMarkingRendersAndAgreement) {
  fs::path out = fresh_dir("label");
  auto r = run_cli("label " + kBuilding + " --up z -d 56 -f +x,-y --verify --json -o " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["views"].size(), 2u);
  for (const auto& v : j["views"]) {
    EXPECT_GE(v["octree_vs_embree"]["identical_rate"].get<double>(), 0.9999);
    EXPECT_EQ(v["octree_vs_embree"]["real_disagreements"], 0);
    const auto& g = v["octree_vs_embree"];  // every mismatch is classified
    EXPECT_EQ(g["covered"].get<uint64_t>(), g["identical"].get<uint64_t>() + g["ties"].get<uint64_t>() +
                                                g["edge_grazes"].get<uint64_t>() +
                                                g["real_disagreements"].get<uint64_t>());
    EXPECT_GE(v["rays_vs_id_buffer"]["identical_rate"].get<double>(), 0.998);
  }
  auto lf = perclod::read_labels(j["labels_file"].get<std::string>());
  ASSERT_EQ(lf.labels.size(), 12456u);
  size_t counts[3] = {0, 0, 0};
  for (size_t t = 0; t < lf.labels.size(); ++t) {
    counts[uint8_t(lf.labels[t])]++;
    // The file's counts and labels obey the rule (perceptible in any view wins, so
    // a summed count can only be checked where it is unambiguous).
    if (lf.traced[t] == 0) {
      EXPECT_EQ(lf.labels[t], perclod::Label::Undisplayable);
    }
    if (lf.imperceptible[t] == 0 && lf.traced[t] > 0) {
      EXPECT_EQ(lf.labels[t], perclod::Label::Perceptible);
    }
  }
  EXPECT_EQ(counts[0], j["labels"]["perceptible"].get<size_t>());
  EXPECT_EQ(counts[2], j["labels"]["undisplayable"].get<size_t>());
  EXPECT_GT(counts[0], 0u);
  EXPECT_GT(counts[2], 0u);  // two facades of four: the back walls cannot be seen
  for (const auto& f : j["marking_renders"]) EXPECT_TRUE(fs::exists(f.get<std::string>())) << f;
  EXPECT_EQ(j["marking_renders"].size(), 4u);  // 2 facades x (view, nearer)
  fs::remove_all(out);
}

// Issue 10 from the command line: a view set with a free view and the top,
// several samples per pixel (recorded in the labels file), and a view too
// close to frame the building tiled into files of its own.
TEST(CliPipeline, LabelTakesViewSetsSamplesAndTilesCloseViews) {
  fs::path out = fresh_dir("label-views");
  auto r = run_cli("label " + kBuilding + " --up z -d 56 --views top,az45el30 --samples 2 --json -o " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["views"].size(), 2u);
  EXPECT_EQ(j["views"][0]["view"], "top");
  EXPECT_EQ(j["samples_per_pixel"], 2);
  EXPECT_EQ(j["combine_views"], "pooled");  // the default
  EXPECT_TRUE(fs::exists(out / "bldg_4018215_az45el30_56m.png"));
  auto lf = perclod::read_labels(j["labels_file"].get<std::string>());
  EXPECT_EQ(lf.samples, 2);
  ASSERT_EQ(lf.views.size(), 2u);
  EXPECT_EQ(lf.views[1].first, "az45el30");

  // 8 m in front of the -y face: the facade overfills one frame, so the view is tiled.
  fs::path near = fresh_dir("label-tiles");
  auto t = run_cli("label " + kBuilding + " --up z -d 8 --views -y --samples 1 --combine-views any --json -o " +
                   near.string());
  ASSERT_EQ(t.exit_code, 0) << t.err;
  auto k = nlohmann::json::parse(t.out);
  EXPECT_EQ(k["combine_views"], "any");
  EXPECT_GT(k["views"].size(), 1u);
  EXPECT_EQ(k["views"][0]["view"], "-y_t0");
  EXPECT_TRUE(fs::exists(near / "bldg_4018215_-y_t0_8m.png"));
  EXPECT_EQ(k["outside_views"], 0);

  // --mask-per-sample: one render per sample offset, one report entry per view.
  fs::path mps = fresh_dir("label-mps");
  auto m = run_cli("label " + kBuilding + " --up z -d 132 --views top --samples 2 --mask-per-sample --json -o " +
                   mps.string());
  ASSERT_EQ(m.exit_code, 0) << m.err;
  auto mj = nlohmann::json::parse(m.out);
  EXPECT_EQ(mj["mask_per_sample"], true);
  ASSERT_EQ(mj["views"].size(), 1u);
  EXPECT_EQ(mj["views"][0]["passes"], 2);
  EXPECT_EQ(perclod::read_labels(mj["labels_file"].get<std::string>()).samples, 2);
  auto both = run_cli("label " + kBuilding + " --up z -d 132 --views top --mask-per-sample --keep-unsampled-surface -o " +
                      mps.string());
  EXPECT_NE(both.exit_code, 0);
  EXPECT_NE(both.err.find("--keep-unsampled-surface"), std::string::npos) << both.err;
  // --samples 16: the 4 x 4 grid from one refined render, labels file and
  // report saying so; with --keep-unsampled-surface an error.
  auto g = run_cli("label " + kBuilding + " --up z -d 427 --views top --samples 16 --json -o " + mps.string());
  ASSERT_EQ(g.exit_code, 0) << g.err;
  auto gj = nlohmann::json::parse(g.out);
  EXPECT_EQ(gj["sample_grid"], 4);
  EXPECT_FALSE(gj["views"][0].contains("passes"));
  EXPECT_EQ(perclod::read_labels(gj["labels_file"].get<std::string>()).samples, 16);
  auto grid_keep =
      run_cli("label " + kBuilding + " --up z -d 427 --views top --samples 16 --keep-unsampled-surface -o " + mps.string());
  EXPECT_NE(grid_keep.exit_code, 0);
  EXPECT_NE(grid_keep.err.find("keep_unsampled_surface"), std::string::npos) << grid_keep.err;
  // --samples auto (the default): each view's choice in the report; a
  // count that is no pattern is refused before any work.
  auto a = run_cli("label " + kBuilding + " --up z -d 427 --views top,-y --samples auto --json -o " + mps.string());
  ASSERT_EQ(a.exit_code, 0) << a.err;
  auto aj = nlohmann::json::parse(a.out);
  EXPECT_EQ(aj["samples_per_pixel"], "auto");
  EXPECT_EQ(aj["sampling_chosen"]["16 (grid)"], 2);
  EXPECT_EQ(aj["views"][1]["sampling"], "16 (grid)");
  EXPECT_EQ(perclod::read_labels(aj["labels_file"].get<std::string>()).samples, 16);  // counts in 1/16 px
  auto three = run_cli("label " + kBuilding + " --up z -d 427 --samples 3 -o " + mps.string());
  EXPECT_NE(three.exit_code, 0);
  EXPECT_NE(three.err.find("--samples"), std::string::npos) << three.err;
  fs::remove_all(out);
  fs::remove_all(near);
  fs::remove_all(mps);
}

TEST(CliPipeline, RunMakesOneLodPerDistanceThatIsNoLargerThanItsInput) {
  fs::path out = fresh_dir("run");
  fs::create_directories(out);
  std::ofstream(out / "job.yaml") << "model: " << kBuilding << "\nup: z\ndistances: [56, 427]\nfacades: all\nout: "
                                  << (out / "result").string() << "\n";
  auto r = run_cli("run " + (out / "job.yaml").string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["lods"].size(), 2u);
  size_t previous = SIZE_MAX;
  for (const auto& lod : j["lods"]) {
    std::string path = lod["lod_file"];
    ASSERT_TRUE(fs::exists(path)) << path;
    perclod::Scene s = perclod::load_scene(path);
    EXPECT_EQ(s.triangle_count(), lod["simplify"]["total_after"].get<size_t>());
    EXPECT_LT(s.triangle_count(), 12456u);
    EXPECT_LE(s.triangle_count(), previous);  // farther never needs more
    previous = s.triangle_count();
    // The default mode bounds what it moves: the perceptible triangles are
    // re-tessellated, not deleted.
    EXPECT_EQ(j["simplify_mode"], "fidelity");
    EXPECT_GT(lod["simplify"]["triangles_after"]["perceptible"].get<size_t>(), 0u);
    // Judged from its four labelling views and the nine held-out views.
    ASSERT_EQ(lod["lod_vs_original"].size(), 13u);
    size_t held_out = 0;
    double worst_changed = 0, worst_silhouette = 0, lowest_ssim = 1;
    for (const auto& v : lod["lod_vs_original"]) {
      EXPECT_GT(v["drawn_pixels"].get<size_t>(), 1000u);
      EXPECT_LE(v["changed_pixels"].get<size_t>(), v["drawn_pixels"].get<size_t>());
      held_out += v["set"] == "held_out";
      worst_changed = std::max(worst_changed, v["changed_fraction"].get<double>());
      worst_silhouette = std::max(worst_silhouette, v["silhouette_mismatch"].get<double>());
      lowest_ssim = std::min(lowest_ssim, v["ssim_covered"].get<double>());
    }
    EXPECT_EQ(held_out, 9u);
    EXPECT_EQ(lod["fidelity"]["worst"]["changed_fraction"].get<double>(), worst_changed);
    EXPECT_EQ(lod["fidelity"]["worst"]["silhouette_mismatch"].get<double>(), worst_silhouette);
    EXPECT_EQ(lod["fidelity"]["worst"]["ssim_covered"].get<double>(), lowest_ssim);
    EXPECT_GT(lowest_ssim, 0.5);
  }
  // Every figure over a limit is a warning on stderr.
  EXPECT_EQ(j["over_limits"].get<size_t>(), j.contains("warnings") ? j["warnings"].size() : 0u);
  EXPECT_TRUE(fs::exists(out / "result" / "bldg_4018215_report.json"));
  // Its HTML page beside it, naming the files it shows relative to itself.
  std::ifstream page(out / "result" / "bldg_4018215_report.html");
  ASSERT_TRUE(page.good());
  const std::string html((std::istreambuf_iterator<char>(page)), std::istreambuf_iterator<char>());
  // Titled by the model file as the config names it.
  EXPECT_NE(html.find("<title>perclod report: " + j["model"].get<std::string>() + "</title>"), std::string::npos);
  EXPECT_NE(html.find("bldg_4018215.obj</title>"), std::string::npos);
  EXPECT_NE(html.find("href=\"bldg_4018215_lod_427m.obj\""), std::string::npos);
  EXPECT_NE(html.find("src=\"bldg_4018215_+x_56m_marking.png\""), std::string::npos);
  for (const auto& lod : j["lods"])
    for (const auto& v : lod["views"])
      EXPECT_TRUE(fs::exists(out / "result" / ("bldg_4018215_" + v["view"].get<std::string>() + "_" +
                                               std::to_string(lod["distance"].get<int>()) + "m.png")));
  // A bad config value names the file and the key, and writes nothing.
  std::ofstream(out / "bad.yaml") << "model: " << kBuilding << "\ndistances: [56, -1]\nout: " << (out / "bad").string() << "\n";
  auto bad = run_cli("run " + (out / "bad.yaml").string());
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("bad.yaml"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("'distances'"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(out / "bad"));
  fs::remove_all(out);
}

// A config for the demo building (Z up) in `dir` with `settings`, writing to dir/<result>.
static std::string job_file(const fs::path& dir, const char* name, const std::string& settings, const char* result) {
  std::ofstream(dir / name) << "model: " << kBuilding << "\nup: z\n" << settings << "out: " << (dir / result).string()
                            << "\n";
  return (dir / name).string();
}

// `perclod run` of the demo building with `settings` in dir/job.yaml, writing to dir/result, with `flags`.
static perclod::test::CliResult run_job(const fs::path& dir, const std::string& settings, const std::string& flags) {
  return run_cli("run " + job_file(dir, "job.yaml", settings, "result") + flags);
}

// A search step's e_perceptible at e_imperceptible = e with the default
// asked 0.5 px: e where tighter, else a quarter of e (kPerceptibleShare) or
// the asked 0.5 px, whichever is looser.
static double expected_e_perceptible(double e) {
  return e < 0.5 ? e : std::max(0.5, perclod::kPerceptibleShare * e);
}

// fidelity_target: the run searches e_imperceptible for the fewest triangles
// within the target in every judged view, and says what it tried.
TEST(CliPipeline, FidelityTargetIsMetAtTheFirstStepWithinIt) {
  fs::path out = fresh_dir("run-target");
  fs::create_directories(out);
  auto r = run_job(out,
                   "distances: [132]\nsamples: 1\njudge_views: az22.5el15\n"
                   "fidelity_target: {max_changed: 0.02, max_silhouette: 0.01}\n",
                   " --json --explain");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  const auto& lod = j["lods"][0];
  ASSERT_TRUE(lod.contains("fidelity_search"));
  const auto& search = lod["fidelity_search"];
  ASSERT_GE(search.size(), 1u);
  // Down the steps to the first within the target, then one try midway
  // between it and the step before (when there is one before).
  size_t first = 0;
  while (first < search.size() && !search[first]["met"].get<bool>()) ++first;
  ASSERT_LT(first, search.size()) << search;
  ASSERT_GT(first, 0u) << "the loosest step must miss this target for the midway try to be tested";
  ASSERT_EQ(search.size(), first + 2) << search;
  const auto& mid = search[first + 1];
  EXPECT_DOUBLE_EQ(mid["e_imperceptible"].get<double>(),
                   std::sqrt(search[first]["e_imperceptible"].get<double>() *
                             search[first - 1]["e_imperceptible"].get<double>()));
  const bool mid_kept =
      mid["met"].get<bool>() && mid["triangles"].get<size_t>() <= search[first]["triangles"].get<size_t>();
  const size_t kept = mid_kept ? first + 1 : first;
  for (size_t i = 0; i < search.size(); ++i)  // the report marks the try it wrote
    EXPECT_EQ(search[i].value("kept", false), i == kept) << search[i];
  EXPECT_EQ(lod["bounds_px"]["imperceptible"], search[kept]["e_imperceptible"]);
  EXPECT_EQ(lod["simplify"]["total_after"], search[kept]["triangles"]);
  // --explain (explain: true): the written LOD's half-edges left, by the rule that refuses them.
  ASSERT_TRUE(lod["simplify"].contains("refused")) << lod["simplify"];
  size_t refused = 0;
  for (const char* rule : {"bound_or_locked", "valence", "topology", "shape", "legal"})
    refused += lod["simplify"]["refused"][rule].get<size_t>();
  EXPECT_GT(refused, 0u);
  EXPECT_EQ(lod["simplify"]["refused"]["total"].get<size_t>(), refused);
  EXPECT_NE(r.err.find("LOD 132 m stopped: " + std::to_string(refused) + " half-edges left: "), std::string::npos)
      << r.err;
  for (const auto& v : lod["lod_vs_original"]) {
    EXPECT_LE(v["changed_fraction"].get<double>(), 0.02) << v["view"];
    EXPECT_LE(v["silhouette_mismatch"].get<double>(), 0.01) << v["view"];
  }
  EXPECT_NE(r.err.find("fidelity target at 132 m"), std::string::npos) << r.err;
  for (const auto& t : search)  // e_perceptible: a quarter of e_imperceptible, never looser than that nor tighter
    EXPECT_EQ(t["e_perceptible"].get<double>(), expected_e_perceptible(t["e_imperceptible"].get<double>())) << t;
  EXPECT_EQ(lod["bounds_px"]["perceptible"], search[kept]["e_perceptible"]);
  EXPECT_EQ(lod["bounds_px"]["undisplayable"], search[kept]["undisplayable"]);
  // keep_undisplayable: auto (the default) measured what deleting would open
  // and chose by it: the default views leave the demo under the limit.
  ASSERT_TRUE(lod["bounds_px"].contains("undisplayable_exposure")) << lod["bounds_px"];
  EXPECT_LE(lod["bounds_px"]["undisplayable_exposure"].get<double>(), perclod::kKeepUndisplayableExposure);
  EXPECT_EQ(search.front()["undisplayable"], "deleted");
  fs::remove_all(out);
}

// When the loosest step already meets the target, looser bounds are tried
// while they meet it and remove triangles (doubling up to
// kFidelitySearchLoosestPx), and the loosest LOD that met it is the one written.
// Every branch of that rule alone, on scripted tries: FidelitySearch in
// tests/pipeline/test_view_sets.cpp.
TEST(CliPipeline, FidelityTargetTriesLooserBoundsWhileTheyMeetIt) {
  fs::path out = fresh_dir("run-target-looser");
  fs::create_directories(out);
  // The 56 m LOD of a run from the four facades with these settings, and the run's stderr.
  auto run = [&](const char* name, const std::string& settings) {
    const std::string config = std::string(name) + ".yaml";
    auto r = run_cli("run " +
                     job_file(out, config.c_str(), "distances: [56]\nviews: facades\nsamples: 1\n" + settings, name) +
                     " --json");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return std::make_pair(r.exit_code == 0 ? nlohmann::json::parse(r.out)["lods"][0] : nlohmann::json(), r.err);
  };
  // Measured: 16 px (e_P 4 px) changes 11.35% of the worst view, 32 px (8 px)
  // 12.39%, the midway 22.6 px 12.17% (all within the perceptual floor,
  // 0.64x, 0.72x and 0.69x).
  const auto [back, back_err] = run("back", "judge_views: none\nfidelity_target: {max_changed: 0.12}\n");
  const auto& tries = back["fidelity_search"];
  ASSERT_EQ(tries.size(), 3u) << tries;
  EXPECT_EQ(tries[0]["e_imperceptible"].get<double>(), perclod::kFidelitySearch[0].e);
  EXPECT_TRUE(tries[0]["met"].get<bool>());
  EXPECT_EQ(tries[1]["e_imperceptible"].get<double>(), 2 * perclod::kFidelitySearch[0].e);
  EXPECT_FALSE(tries[1]["met"].get<bool>());
  EXPECT_DOUBLE_EQ(tries[2]["e_imperceptible"].get<double>(), std::sqrt(2.0) * perclod::kFidelitySearch[0].e);
  EXPECT_FALSE(tries[2]["met"].get<bool>());
  // The LOD written is the one that met it, made again.
  EXPECT_TRUE(tries[0].value("kept", false));
  EXPECT_FALSE(tries[1].contains("kept"));
  EXPECT_FALSE(tries[2].contains("kept"));
  EXPECT_EQ(back["bounds_px"]["imperceptible"], tries[0]["e_imperceptible"]);
  EXPECT_EQ(back["simplify"]["total_after"], tries[0]["triangles"]);
  EXPECT_FALSE(back["simplify"].contains("refused"));  // only with explain: true
  for (const auto& v : back["lod_vs_original"]) {
    EXPECT_LE(v["changed_fraction"].get<double>(), 0.12) << v["view"];
    // Without held-out views the labelling views' floors are measured too.
    EXPECT_GT(v["visible_floor"].get<double>(), 0) << v["view"];
  }
  EXPECT_EQ(back_err.find("no bound meets"), std::string::npos) << back_err;
  // A target every looser step meets: up while each removes triangles (or to
  // the loosest), each with no more triangles than the one before: no limit
  // at all. Measured: every step up to 1024 px removes triangles (4,614 at
  // 16 px, 3,858 at 1024 px; undisplayable triangles kept within 4 px, as
  // keep_undisplayable: auto decides for the four facades).
  const auto all = run("all", "judge_views: az22.5el15\nfidelity_target: {max_changed: 1, max_visible: 0}\n").first;
  const auto& up = all["fidelity_search"];
  ASSERT_GE(up.size(), 2u) << up;
  for (size_t i = 0; i < up.size(); ++i) {
    EXPECT_TRUE(up[i]["met"].get<bool>()) << up[i];
    EXPECT_EQ(up[i].value("kept", false), i + 1 == up.size()) << up[i];
    EXPECT_EQ(up[i]["e_imperceptible"].get<double>(), perclod::kFidelitySearch[0].e * double(1u << i));
    if (i > 0 && i + 1 < up.size()) {  // every try before the last removed triangles
      EXPECT_LT(up[i]["triangles"].get<size_t>(), up[i - 1]["triangles"].get<size_t>()) << up[i];
    }
  }
  const double last_e = up.back()["e_imperceptible"].get<double>();
  // Past 64 px, the bound an earlier version of the looser tries stopped at
  // (BENCHMARKS.md#with-a-fidelity-target: 16 to 128 px meet this target).
  EXPECT_GT(last_e, 64.0);
  EXPECT_TRUE(last_e == perclod::kFidelitySearchLoosestPx ||
              up.back()["triangles"] == up[up.size() - 2]["triangles"]) << up;
  EXPECT_EQ(all["bounds_px"]["imperceptible"].get<double>(), last_e);
  EXPECT_EQ(all["simplify"]["total_after"], up.back()["triangles"]);
  fs::remove_all(out);
}

TEST(CliPipeline, FidelityTargetNoLooserStepMeetsTriesEveryStep) {
  fs::path out = fresh_dir("run-target-all");
  fs::create_directories(out);
  // A target only an unchanged picture meets: every step is tried, both
  // bounds tighten to 0 px, the last steps keep undisplayable triangles
  // (collapsed within the step's bound) instead of deleting them, and the
  // last, which moves and deletes nothing, changes no pixel. (Undisplayable
  // triangles deleted as asked: the four facades alone leave so much unseen
  // that keep_undisplayable: auto would keep them from the first step.
  // free_topology: false: past the half-edge rules, zero-error collapses
  // re-tessellate the demo's coplanar overlapping walls, which changes
  // which of two equal depths a pixel shows: 0.21% of the pixels.)
  auto none = run_cli("run " +
                      job_file(out, "none.yaml",
                               "distances: [427]\nviews: facades\nsamples: 1\njudge_views: none\n"
                               "keep_undisplayable: false\nfree_topology: false\nfidelity_target: {max_changed: 0}\n",
                               "none") +
                      " --json");
  ASSERT_EQ(none.exit_code, 0) << none.err;
  const auto none_report = nlohmann::json::parse(none.out);
  const auto& all = none_report["lods"][0];
  ASSERT_EQ(all["fidelity_search"].size(), std::size(perclod::kFidelitySearch));
  size_t deleting = 0;
  for (size_t i = 0; i < std::size(perclod::kFidelitySearch); ++i) {
    const auto& t = all["fidelity_search"][i];
    const perclod::FidelitySearchStep& step = perclod::kFidelitySearch[i];
    EXPECT_EQ(t["met"].get<bool>(), i + 1 == std::size(perclod::kFidelitySearch)) << t;
    EXPECT_EQ(t.value("kept", false), i + 1 == std::size(perclod::kFidelitySearch)) << t;
    EXPECT_EQ(t["e_imperceptible"].get<double>(), step.e);
    EXPECT_EQ(t["e_perceptible"].get<double>(), expected_e_perceptible(step.e));
    if (step.keep_undisplayable) {
      EXPECT_EQ(t["undisplayable"], "collapsed") << t;
      EXPECT_EQ(t["e_undisplayable"].get<double>(), step.e) << t;
    } else {
      EXPECT_EQ(t["undisplayable"], "deleted") << t;
      EXPECT_FALSE(t.contains("e_undisplayable")) << t;
      ++deleting;
    }
  }
  EXPECT_GE(deleting, 5u);  // the loose steps delete, as the default does
  EXPECT_TRUE(perclod::kFidelitySearch[std::size(perclod::kFidelitySearch) - 1].keep_undisplayable);
  EXPECT_EQ(all["bounds_px"]["perceptible"].get<double>(), 0.0);
  EXPECT_EQ(all["bounds_px"]["imperceptible"].get<double>(), 0.0);
  EXPECT_EQ(all["bounds_px"]["undisplayable"], "collapsed");
  EXPECT_EQ(all["bounds_px"]["e_undisplayable"].get<double>(), 0.0);
  // Keeping the undisplayable triangles keeps more of them than deleting.
  EXPECT_GT(all["fidelity_search"].back()["triangles"].get<double>(),
            all["fidelity_search"][deleting - 1]["triangles"].get<double>());
  EXPECT_EQ(all["simplify"]["undisplayable_faces_deleted"].get<double>(), 0.0) << all["simplify"];
  EXPECT_EQ(all["fidelity"]["worst"]["changed_fraction"].get<double>(), 0.0) << all["fidelity"];
  EXPECT_EQ(none.err.find("no bound meets the fidelity target"), std::string::npos) << none.err;
  fs::remove_all(out);
}

// --strict turns figures over the limits into a failure after every output
// is written; a fidelity target needs fidelity mode.
TEST(CliPipeline, StrictFailsOverLimitsAfterWritingEverything) {
  fs::path out = fresh_dir("run-strict");
  fs::create_directories(out);
  // Limits nobody meets: warnings name the view, and --strict fails.
  auto t = run_cli("run " +
                   job_file(out, "tight.yaml",
                            "distances: [427]\nviews: facades\nsamples: 1\njudge_views: none\n"
                            "max_changed: 0\nmax_silhouette: 0\nmin_ssim: 1\nsimplify: paper\n",
                            "tight") +
                   " --strict");
  EXPECT_EQ(t.exit_code, 1) << t.err;
  EXPECT_NE(t.err.find("warning:"), std::string::npos) << t.err;
  EXPECT_NE(t.err.find("from view +x (labelling) changed_fraction"), std::string::npos) << t.err;
  EXPECT_NE(t.err.find("from view +x (labelling) ssim_covered is 0."), std::string::npos) << t.err;  // not a %
  EXPECT_NE(t.err.find("(limit 1)"), std::string::npos) << t.err;
  EXPECT_NE(t.err.find("strict"), std::string::npos) << t.err;
  EXPECT_TRUE(fs::exists(out / "tight" / "bldg_4018215_report.json"));  // every output written
  EXPECT_TRUE(fs::exists(out / "tight" / "bldg_4018215_lod_427m.obj"));
  // A fidelity target needs fidelity mode.
  std::ofstream(out / "bad.yaml") << "model: " << kBuilding
                                  << "\ndistances: [56]\nsimplify: paper\nfidelity_target: {max_changed: 0.02}\n";
  auto b = run_cli("run " + (out / "bad.yaml").string());
  EXPECT_EQ(b.exit_code, 1);
  EXPECT_NE(b.err.find("'fidelity_target' applies only to 'simplify: fidelity'"), std::string::npos) << b.err;
  fs::remove_all(out);
}

// tighten_to_limits (the default in fidelity mode): a LOD over its limits,
// but within kTightenReach of them, is made again at the tighter steps until
// one is within; out of reach, or turned off, the LOD stays at the asked
// bounds and is flagged. Asked at 0.5 px (the default until 0.8; the
// halvings from the default 8 px: the next test). Figures of the demo at
// 132 m, one sample, judged also from az22.5el15: 2.56% changed at 0.5 px,
// 0.47% at 0.25 px.
TEST(CliPipeline, TightenToLimitsRemakesALodJustOverItsLimits) {
  fs::path out = fresh_dir("run-tighten");
  fs::create_directories(out);
  auto run = [&](const char* name, const std::string& settings) {
    std::ofstream(out / name) << "model: " << kBuilding << "\nup: z\nsamples: 1\n"
                              << "judge_views: az22.5el15\ndebug_images: false\ntileset: false\n"
                              << "e_imperceptible: 0.5\n"
                              << (settings.find("distances") == std::string::npos ? "distances: [132]\n" : "")
                              << settings << "out: " << (out / name).string() << ".out\n";
    auto r = run_cli("run " + (out / name).string() + " --json");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    j["stderr"] = r.err;
    return j;
  };
  const auto asked = run("off.yaml", "max_changed: 0.01\ntighten_to_limits: false\n");
  const auto& a = asked["lods"][0];
  const double at_asked = a["fidelity"]["worst"]["changed_fraction"].get<double>();
  ASSERT_GT(at_asked, 0.01) << "the asked bounds must miss this limit for the test to mean anything";
  ASSERT_LE(at_asked, perclod::kTightenReach * 0.01);
  EXPECT_FALSE(a.contains("tighten_to_limits"));
  EXPECT_EQ(a["bounds_px"]["imperceptible"].get<double>(), 0.5);

  const auto tightened = run("on.yaml", "max_changed: 0.01\n");
  const auto& t = tightened["lods"][0];
  ASSERT_TRUE(t.contains("tighten_to_limits")) << t;
  const auto& tries = t["tighten_to_limits"];
  ASSERT_GE(tries.size(), 2u);
  EXPECT_EQ(tries[0]["triangles"], a["simplify"]["total_after"]);  // the asked bounds first
  for (const auto& x : tries) EXPECT_GT(x["seconds_simplify"].get<double>(), 0) << x;  // what each try cost
  EXPECT_FALSE(tries[0]["met"].get<bool>());
  EXPECT_TRUE(tries.back()["met"].get<bool>());
  for (size_t i = 1; i + 1 < tries.size(); ++i) EXPECT_FALSE(tries[i]["met"].get<bool>());
  for (size_t i = 0; i < tries.size(); ++i) EXPECT_EQ(tries[i].value("kept", false), i + 1 == tries.size()) << tries[i];
  EXPECT_EQ(t["bounds_px"]["imperceptible"], tries.back()["e_imperceptible"]);
  EXPECT_LT(t["bounds_px"]["imperceptible"].get<double>(), 0.5);
  EXPECT_EQ(t["simplify"]["total_after"], tries.back()["triangles"]);
  EXPECT_GE(t["simplify"]["total_after"].get<double>(), a["simplify"]["total_after"].get<double>());
  for (const auto& v : t["lod_vs_original"]) EXPECT_LE(v["changed_fraction"].get<double>(), 0.01) << v["view"];
  EXPECT_EQ(t["fidelity"]["over_limits"].size(), 0u);
  EXPECT_EQ(tightened["over_limits"], 0);
  EXPECT_NE(tightened["stderr"].get<std::string>().find("tighten to limits at 132 m"), std::string::npos);
  EXPECT_EQ(tightened["stderr"].get<std::string>().find("warning:"), std::string::npos) << tightened["stderr"];

  // Out of reach (the asked LOD is more than kTightenReach x over): nothing
  // is tried, the LOD is the asked one, flagged.
  const auto far = run("far.yaml", "max_changed: " + std::to_string(at_asked / (perclod::kTightenReach + 1)) + "\n");
  EXPECT_FALSE(far["lods"][0].contains("tighten_to_limits"));
  EXPECT_EQ(far["lods"][0]["simplify"]["total_after"], a["simplify"]["total_after"]);
  EXPECT_GT(far["over_limits"].get<int>(), 0);

  // Within reach but no tighter step is within: at 56 m the asked bounds
  // change 0.153% and no step gets below 0.12% (0.25 px changes 0.156%,
  // 0.125 px with undisplayable triangles kept within it 0.125%). Every
  // step is tried and the tightest LOD is kept, flagged (the asked one,
  // until 0.9.1).
  const auto none = run("none.yaml", "distances: [56]\nmax_changed: 0.0012\n");
  const auto& n = none["lods"][0];
  ASSERT_TRUE(n.contains("tighten_to_limits")) << n;
  const auto& tries_n = n["tighten_to_limits"];
  const auto& first = tries_n[0];
  const auto& last = tries_n.back();
  ASSERT_GT(first["worst"]["changed_fraction"].get<double>(), 0.0012);
  ASSERT_LE(first["worst"]["changed_fraction"].get<double>(), perclod::kTightenReach * 0.0012);
  EXPECT_EQ(tries_n.size(), 1 + std::size(perclod::kTightenSteps));  // the asked bounds first
  for (const auto& x : tries_n) EXPECT_FALSE(x["met"].get<bool>()) << x;
  for (size_t i = 0; i < tries_n.size(); ++i)  // the tightest is what is written
    EXPECT_EQ(tries_n[i].value("kept", false), i + 1 == tries_n.size()) << tries_n[i];
  EXPECT_EQ(n["simplify"]["total_after"], last["triangles"]);
  EXPECT_GT(last["triangles"].get<double>(), first["triangles"].get<double>());
  EXPECT_EQ(n["bounds_px"]["imperceptible"].get<double>(), 0.125);
  EXPECT_NE(n["bounds_px"]["undisplayable"], "deleted");
  EXPECT_NE(none["stderr"].get<std::string>().find("none within; the tightest tried is kept"), std::string::npos);
  EXPECT_EQ(n["fidelity"]["worst"], last["worst"]);  // the last try's LOD, not made again
  EXPECT_LT(n["fidelity"]["worst"]["changed_fraction"].get<double>(), first["worst"]["changed_fraction"].get<double>());
  EXPECT_GT(none["over_limits"].get<int>(), 0);

  // Only fidelity mode tightens.
  std::ofstream(out / "bad.yaml") << "model: " << kBuilding << "\ndistances: [56]\nsimplify: paper\ntighten_to_limits: true\n";
  auto b = run_cli("run " + (out / "bad.yaml").string());
  EXPECT_EQ(b.exit_code, 1);
  EXPECT_NE(b.err.find("'tighten_to_limits' applies only to 'simplify: fidelity'"), std::string::npos) << b.err;
  fs::remove_all(out);
}

// The default bounds (e_I 8 px, e_P 0.5 px): a LOD over the perceptual
// floor is made again with e_I halved until one is within it, e_P never
// loosened, then once midway between that halving and the one before
// (tighten_midway), kept when within with no more triangles. Measured: the
// demo at 427 m from the default views, one sample, judged also from
// az22.5el15, is over the floor at 8 and 4 px (3,130 and 3,199 triangles),
// within it at 2 px (3,570; 0.72x the floor) and at the midway 2.83 px
// (3,294; 0.95x), which is written.
TEST(CliPipeline, TheDefaultBoundsHalveUntilTheLodIsWithinTheFloor) {
  fs::path out = fresh_dir("run-halve");
  fs::create_directories(out);
  auto r = run_job(out, "distances: [427]\nsamples: 1\njudge_views: az22.5el15\ndebug_images: false\ntileset: false\n",
                   " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto lod = nlohmann::json::parse(r.out)["lods"][0];
  ASSERT_TRUE(lod.contains("tighten_to_limits")) << "the asked 8 px must miss the floor for the test to mean anything";
  const auto& tries = lod["tighten_to_limits"];
  ASSERT_GE(tries.size(), 4u) << tries;
  const size_t n = tries.size() - 1;  // the halvings (from the asked bounds on), then the midway try
  EXPECT_EQ(tries[0]["e_imperceptible"].get<double>(), perclod::kDefaultBoundImperceptiblePx);
  for (size_t i = 0; i < tries.size(); ++i) {
    EXPECT_LE(tries[i]["e_perceptible"].get<double>(), 0.5) << tries[i];  // never loosened
    if (i == 0 || i == n) continue;
    EXPECT_EQ(tries[i]["e_imperceptible"].get<double>(), tries[i - 1]["e_imperceptible"].get<double>() / 2);
    EXPECT_EQ(tries[i]["met"].get<bool>(), i + 1 == n) << tries[i];
    EXPECT_GE(tries[i]["triangles"].get<size_t>(), tries[i - 1]["triangles"].get<size_t>()) << tries[i];
  }
  EXPECT_FALSE(tries[0]["met"].get<bool>());
  const auto& met = tries[n - 1];
  const auto& mid = tries[n];
  EXPECT_GE(met["e_imperceptible"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(mid["e_imperceptible"].get<double>(), met["e_imperceptible"].get<double>() * std::sqrt(2.0));
  const bool mid_kept = mid["met"].get<bool>() && mid["triangles"].get<size_t>() <= met["triangles"].get<size_t>();
  EXPECT_TRUE(mid_kept) << "measured: the midway 2.83 px is within the floor with fewer triangles";
  for (size_t i = 0; i < tries.size(); ++i)  // the report marks the try it wrote
    EXPECT_EQ(tries[i].value("kept", false), i == (mid_kept ? n : n - 1)) << tries[i];
  const auto& kept = mid_kept ? mid : met;
  EXPECT_EQ(lod["bounds_px"]["imperceptible"], kept["e_imperceptible"]);
  EXPECT_EQ(lod["simplify"]["total_after"], kept["triangles"]);
  for (const auto& v : lod["lod_vs_original"]) EXPECT_LE(v["visible_ratio"].get<double>(), 1.0) << v["view"];
  EXPECT_EQ(r.err.find("warning:"), std::string::npos) << r.err;
  fs::remove_all(out);
}

// debug_images: false writes no image at all, and changes nothing else: the
// labels, the LODs and every figure of the report are those of a run with
// them (which encodes its images on a second thread). With them, every
// labelling render has its marking image beside it (coloured from its ID
// buffer), and the near marking only with marking_near.
TEST(CliPipeline, RunWithoutDebugImagesWritesNoneAndTheSameResults) {
  fs::path out = fresh_dir("run-images");
  fs::create_directories(out);
  auto job = [&](const std::string& name, const std::string& extra) {
    std::ofstream(out / (name + ".yaml")) << "model: " << kBuilding << "\nup: z\ndistances: [56, 427]\n"
                                          << "views: facades,az45el30\njudge_views: az22.5el45\nout: "
                                          << (out / name).string() << "\n" << extra;
    auto r = run_cli("run " + (out / (name + ".yaml")).string() + " --json");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out);
  };
  const auto with = job("with", "");
  const auto without = job("without", "debug_images: false\n");
  auto files = [&](const std::string& name, const std::string& ext) {
    std::vector<std::string> f;
    for (const auto& e : fs::directory_iterator(out / name))
      if (e.path().extension() == ext) f.push_back(e.path().filename().string());
    std::sort(f.begin(), f.end());
    return f;
  };
  auto bytes = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_TRUE(files("without", ".png").empty());
  const auto pngs = files("with", ".png");
  for (const auto& lod : with["lods"])
    for (const auto& v : lod["views"]) {
      const std::string stem = "bldg_4018215_" + v["view"].get<std::string>() + "_" +
                               std::to_string(lod["distance"].get<int>()) + "m";
      for (const char* suffix : {".png", "_marking.png", "_simulated.png", "_lod_vs_original.png"})
        EXPECT_TRUE(std::binary_search(pngs.begin(), pngs.end(), stem + suffix)) << stem + suffix;
    }
  for (const auto& f : pngs) EXPECT_EQ(f.find("_marking_near"), std::string::npos) << f;
  for (const char* ext : {".txt", ".obj"}) {
    const auto a = files("with", ext), b = files("without", ext);
    ASSERT_EQ(a, b);
    ASSERT_FALSE(a.empty());
    for (const auto& f : a) EXPECT_EQ(bytes(out / "with" / f), bytes(out / "without" / f)) << f;
  }
  ASSERT_EQ(with["lods"].size(), without["lods"].size());
  for (size_t k = 0; k < with["lods"].size(); ++k) {
    const auto &a = with["lods"][k], &b = without["lods"][k];
    EXPECT_EQ(a["labels"], b["labels"]);
    EXPECT_EQ(a["simplify"]["total_after"], b["simplify"]["total_after"]);
    ASSERT_EQ(a["lod_vs_original"].size(), b["lod_vs_original"].size());
    for (size_t v = 0; v < a["lod_vs_original"].size(); ++v)
      for (const char* key : {"view", "drawn_pixels", "changed_pixels", "ssim_covered", "coverage_changed_pixels"})
        EXPECT_EQ(a["lod_vs_original"][v][key], b["lod_vs_original"][v][key]) << key;
  }
  // The report pages link only files that exist: without debug images no
  // render, marking or comparison picture is linked.
  for (const char* name : {"with", "without"}) {
    const std::string page = bytes(out / name / "bldg_4018215_report.html");
    const std::regex link("(?:src|href)=\"([^\"#:]+)\"");
    size_t images = 0;
    for (auto it = std::sregex_iterator(page.begin(), page.end(), link); it != std::sregex_iterator(); ++it) {
      const std::string target = (*it)[1].str();
      EXPECT_TRUE(fs::exists(out / name / target)) << name << ": " << target;
      images += target.size() > 4 && target.compare(target.size() - 4, 4, ".png") == 0;
    }
    if (std::string(name) == "with") EXPECT_GT(images, 10u);
    else EXPECT_EQ(images, 0u);
  }
  fs::remove_all(out);
}
