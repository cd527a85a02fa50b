// Issue 12 (reliability): every command fed generated bad input. For each
// case: the exit status, stderr starting with "perclod: error:" and naming
// the file (or option) concerned, and nothing left under a final output name
// or a .tmp-* name in the output directory, whose earlier content survives.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_util.h"

namespace {

using perclod::test::run_cli;
namespace fs = std::filesystem;

const std::string kCube =
    "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv -1 -1 2\nv 1 -1 2\nv 1 1 2\nv -1 1 2\n"
    "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
const std::string kDisplay = "width: 96\nheight: 64\ndpi: 86.27\nviewer_distance_m: 0.5\n";

struct Fixture {
  fs::path dir, out;
  std::string file(const std::string& name, const std::string& text) const {
    std::ofstream((dir / name).string()) << text;
    return (dir / name).string();
  }
  std::string path(const std::string& name) const { return (dir / name).string(); }
};

std::string labels_file(size_t n, const std::string& model_line, const std::string& line = "I 2 1") {
  std::string s = "perclod-labels 1\n" + model_line + "triangles " + std::to_string(n) + "\nviews 0\n";
  for (size_t i = 0; i < n; ++i) s += line + "\n";
  return s;
}

struct Case {
  std::string name;
  std::string args;                // after "perclod"; {D} is the fixture dir, {O} the output dir
  int exit_code;
  std::vector<std::string> names;  // stderr holds each (the file or option concerned)
};

std::string expand(std::string s, const Fixture& f) {
  for (auto [key, value] : {std::pair{std::string("{D}"), f.dir.string()}, std::pair{std::string("{O}"), f.out.string()}})
    for (size_t at; (at = s.find(key)) != std::string::npos;) s.replace(at, key.size(), value);
  return s;
}

Fixture make_fixture() {
  Fixture f;
  f.dir = perclod::test::fresh_dir("cli-errors", true);
  f.out = f.dir / "out";
  f.file("cube.obj", kCube);
  // Same triangle count, one vertex moved: another model.
  std::string other = kCube;
  other.replace(0, 9, "v -1 -1 1");
  f.file("other.obj", other);
  f.file("display.yaml", kDisplay);
  f.file("display-nodpi.yaml", "width: 96\nheight: 64\nviewer_distance_m: 0.5\n");
  f.file("display-typo.yaml", kDisplay + "viewer_distance: 0.5\n");
  // Labels files (the cube has 12 triangles).
  f.file("neg.txt", labels_file(12, "", "P -5 -7"));
  f.file("more.txt", labels_file(12, "", "I 3 4"));
  f.file("trailing.txt", labels_file(12, "") + "P 1 0\n");
  f.file("minus.txt", "perclod-labels 1\ntriangles -1\nviews 0\n");
  f.file("huge.txt", "perclod-labels 1\ntriangles 99999999999\nviews 0\nP 1 0\n");
  f.file("foreign.txt", labels_file(12, "model 12 0123456789abcdef\n"));
  // Configs.
  const std::string base = "model: cube.obj\ndisplay: display.yaml\ndistances: [56]\nout: " + f.out.string() + "\n";
  f.file("typo.yaml", base + "verfy: true\n");
  f.file("dup.yaml", base + "model: other.obj\n");
  f.file("qem.yaml", base + "simplify: qem\n");
  f.file("abc.yaml", "model: cube.obj\ndisplay: display.yaml\ndistances: [abc]\nout: " + f.out.string() + "\n");
  f.file("facades.yaml", base + "facades: +q\n");
  f.file("views.yaml", base + "views: [facades, ring0]\n");
  f.file("spp.yaml", base + "samples: 3\n");
  f.file("ok.yaml", base);
  f.file("noout.yaml", "model: cube.obj\ndistances: [56]\nout: \"\"\n");
  f.file("nomodel.yaml", "model: gone.obj\ndistances: [56]\nout: " + f.out.string() + "\n");
  f.file("nodpi.yaml", "model: cube.obj\ndisplay: display-nodpi.yaml\ndistances: [56]\nout: " + f.out.string() + "\n");
  f.file("ratio.yaml", base + "ratio: 2\n");
  f.file("cluster.yaml", base + "simplify: cluster\n");
  return f;
}

const std::vector<Case>& cases() {
  static const std::vector<Case> c = {
      // info
      {"info_missing_model", "info {D}/gone.obj", 1, {"{D}/gone.obj"}},
      // render
      {"render_distance_0", "render {D}/cube.obj -d 0 -o {O}", 1, {"--distance"}},
      {"render_missing_display", "render {D}/cube.obj -d 56 --display {D}/gone.yaml -o {O}", 1, {"{D}/gone.yaml"}},
      {"render_display_without_dpi", "render {D}/cube.obj -d 56 --display {D}/display-nodpi.yaml -o {O}", 1,
       {"{D}/display-nodpi.yaml", "'dpi'"}},
      {"render_display_unknown_key", "render {D}/cube.obj -d 56 --display {D}/display-typo.yaml -o {O}", 1,
       {"{D}/display-typo.yaml", "viewer_distance'"}},
      {"render_bad_facade", "render {D}/cube.obj --up z -d 56 -f +z -o {O}", 1, {"--views", "+z"}},
      // label
      {"label_distance_0", "label {D}/cube.obj -d 0 -o {O}", 1, {"--distance"}},
      {"label_no_distance", "label {D}/cube.obj -o {O}", 2, {"--distance"}},
      {"label_scale_0", "label {D}/cube.obj -d 56 --scale 0 -o {O}", 1, {"--scale"}},
      {"label_unknown_option", "label {D}/cube.obj -d 56 --bogus -o {O}", 2, {"--bogus"}},
      {"label_missing_display", "label {D}/cube.obj -d 56 --display {D}/gone.yaml -o {O}", 1, {"{D}/gone.yaml"}},
      {"label_missing_model", "label {D}/gone.obj -d 56 --display {D}/display.yaml -o {O}", 1, {"{D}/gone.obj"}},
      // simplify
      {"simplify_missing_labels", "simplify {D}/cube.obj -d 56 --labels {D}/gone.txt -o {O}", 1, {"{D}/gone.txt"}},
      {"simplify_negative_counts", "simplify {D}/cube.obj -d 56 --labels {D}/neg.txt -o {O}", 1, {"{D}/neg.txt:4"}},
      {"simplify_more_imperceptible", "simplify {D}/cube.obj -d 56 --labels {D}/more.txt -o {O}", 1,
       {"{D}/more.txt:4", "more imperceptible"}},
      {"simplify_trailing_line", "simplify {D}/cube.obj -d 56 --labels {D}/trailing.txt -o {O}", 1,
       {"{D}/trailing.txt:16"}},
      {"simplify_triangles_minus_1", "simplify {D}/cube.obj -d 56 --labels {D}/minus.txt -o {O}", 1,
       {"{D}/minus.txt:2"}},
      {"simplify_triangles_huge", "simplify {D}/cube.obj -d 56 --labels {D}/huge.txt -o {O}", 1,
       {"{D}/huge.txt:2"}},
      {"simplify_labels_of_another_model", "simplify {D}/cube.obj -d 56 --labels {D}/foreign.txt -o {O}", 1,
       {"{D}/foreign.txt", "{D}/cube.obj"}},
      {"simplify_qem_without_target", "simplify {D}/cube.obj -d 56 --mode qem -o {O}", 1, {"--target"}},
      {"simplify_bounded_without_labels", "simplify {D}/cube.obj -d 56 --mode bounded -o {O}", 1, {"--labels"}},
      {"simplify_distance_0", "simplify {D}/cube.obj -d 0 --mode cluster -o {O}", 1, {"--distance"}},
      {"label_bad_views", "label {D}/cube.obj -d 56 --views facades,az10el95 -o {O}", 1, {"--views", "az10el95"}},
      {"label_bad_samples", "label {D}/cube.obj -d 56 --samples 3 -o {O}", 1, {"--samples"}},
      {"label_too_close_to_frame", "label {D}/cube.obj -d 0.0001 --views +x -o {O}", 1, {"tiles", "too close"}},
      // generate
      {"generate_triangles_0", "generate facade --triangles 0 {O}/facade.obj", 1, {"--triangles"}},
      // perceive
      {"perceive_missing_image", "perceive {D}/gone.png -o {O}", 1, {"{D}/gone.png"}},
      // run
      {"run_missing_config", "run {D}/gone.yaml", 1, {"{D}/gone.yaml"}},
      {"run_unknown_key", "run {D}/typo.yaml", 1, {"{D}/typo.yaml", "verfy"}},
      {"run_duplicate_model", "run {D}/dup.yaml", 1, {"{D}/dup.yaml", "'model'"}},
      {"run_qem_without_target", "run {D}/qem.yaml", 1, {"{D}/qem.yaml", "'target'"}},
      {"run_distance_not_a_number", "run {D}/abc.yaml", 1, {"{D}/abc.yaml", "'distances'"}},
      {"run_bad_facades", "run {D}/facades.yaml", 1, {"{D}/facades.yaml", "'facades'"}},
      {"run_bad_views", "run {D}/views.yaml", 1, {"{D}/views.yaml", "'views'", "ring0"}},
      {"run_bad_views_option", "run {D}/ok.yaml --views tops", 1, {"--views", "tops"}},
      {"run_bad_samples", "run {D}/spp.yaml", 1, {"{D}/spp.yaml", "'samples'"}},
      {"run_empty_out", "run {D}/noout.yaml", 1, {"{D}/noout.yaml", "'out'"}},
      {"run_missing_model", "run {D}/nomodel.yaml", 1, {"{D}/nomodel.yaml", "gone.obj"}},
      {"run_display_without_dpi", "run {D}/nodpi.yaml", 1, {"display-nodpi.yaml", "'dpi'"}},
      {"run_ratio_out_of_range", "run {D}/ratio.yaml", 1, {"{D}/ratio.yaml", "'ratio'"}},
      {"run_explain_cluster", "run {D}/cluster.yaml --explain", 1, {"--explain", "{D}/cluster.yaml", "cluster"}},
      {"run_no_config", "run", 2, {"CONFIG"}},
  };
  return c;
}

TEST(CliErrors, EveryBadInputFailsCleanly) {
  Fixture f = make_fixture();
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    fs::remove_all(f.out);
    fs::create_directories(f.out);
    f.file("out/keep.txt", "earlier output\n");  // bad input never loses what was good
    auto r = run_cli(expand(c.args, f));
    EXPECT_EQ(r.exit_code, c.exit_code) << r.err;
    // One error line, the last one (a model may have been loaded before it).
    std::string line, last;
    int error_lines = 0;
    for (std::istringstream lines(r.err); std::getline(lines, line);) {
      error_lines += line.rfind("perclod: error: ", 0) == 0;
      last = line;
    }
    EXPECT_EQ(error_lines, 1) << r.err;
    EXPECT_EQ(last.rfind("perclod: error: ", 0), 0u) << r.err;
    for (const auto& n : c.names) EXPECT_NE(last.find(expand(n, f)), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    std::vector<std::string> left;
    for (const auto& e : fs::recursive_directory_iterator(f.out)) left.push_back(e.path().filename().string());
    EXPECT_EQ(left, std::vector<std::string>{"keep.txt"});
    std::ifstream keep(f.out / "keep.txt");
    std::stringstream ss;
    ss << keep.rdbuf();
    EXPECT_EQ(ss.str(), "earlier output\n");
  }
  fs::remove_all(f.dir);
}

TEST(CliErrors, HelpAndVersionStillExitZero) {
  for (const char* args : {"--help", "run --help", "simplify --help", "--version"}) {
    auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 0) << args << r.err;
    EXPECT_FALSE(r.out.empty()) << args;
  }
}

// Labels written by `perclod label` carry the model's fingerprint; simplify
// accepts them for that model and refuses them for another one with the same
// triangle count, naming both files.
TEST(CliErrors, LabelsFingerprintTiesLabelsToTheirModel) {
  Fixture f = make_fixture();
  auto l = run_cli("label " + f.path("cube.obj") + " -d 20 --display " + f.path("display.yaml") + " -o " +
                   f.out.string());
  ASSERT_EQ(l.exit_code, 0) << l.err;
  const std::string labels = (f.out / "cube_labels_20m.txt").string();
  std::ifstream in(labels);
  std::string magic, model;
  std::getline(in, magic);
  std::getline(in, model);
  EXPECT_EQ(model.rfind("model 12 ", 0), 0u) << model;
  EXPECT_EQ(model.size(), 9u + 16u) << model;
  auto ok = run_cli("simplify " + f.path("cube.obj") + " -d 20 --labels " + labels + " -o " + f.path("lod"));
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  auto bad = run_cli("simplify " + f.path("other.obj") + " -d 20 --labels " + labels + " -o " + f.path("lod2"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("\nperclod: error: " + labels + ": "), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find(f.path("other.obj")), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(f.path("lod2")));
  fs::remove_all(f.dir);
}

// A LOD with nothing displayable (the cube from 100 km) is written, with a
// warning on stderr and "empty": true in the report.
TEST(CliErrors, EmptyLodIsWrittenWithAWarning) {
  Fixture f = make_fixture();
  f.file("far.yaml", "model: cube.obj\ndisplay: display.yaml\ndistances: [100000]\nfacades: +x\nout: " +
                         f.out.string() + "\n");
  auto r = run_cli("run " + f.path("far.yaml") + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("perclod: warning: " + (f.out / "cube_lod_100000m.obj").string()), std::string::npos) << r.err;
  auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["lods"].size(), 1u);
  EXPECT_EQ(j["lods"][0]["empty"], true);
  EXPECT_EQ(j["warnings"].size(), 1u);
  EXPECT_TRUE(fs::exists(f.out / "cube_lod_100000m.obj"));
  fs::remove_all(f.dir);
}

}  // namespace

namespace {

// simplify: qem could never work from a config (no target key); now it can.
TEST(CliErrors, QemConfigWithTargetRuns) {
  Fixture f = make_fixture();
  f.file("qem-ok.yaml", "model: cube.obj\ndisplay: display.yaml\ndistances: [20]\nfacades: +x\nsimplify: qem\n"
                        "target: 6\nout: " + f.out.string() + "\n");
  auto r = run_cli("run " + f.path("qem-ok.yaml") + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["simplify_mode"], "qem");
  EXPECT_LE(j["lods"][0]["simplify"]["total_after"].get<size_t>(), 6u);
  EXPECT_TRUE(fs::exists(f.out / "cube_lod_20m.obj"));
  fs::remove_all(f.dir);
}

}  // namespace
