// Issue 12 (reliability): every command fed generated bad input. For each
// case: the exit status, stderr starting with "perclod: error:" and naming
// the file (or option) concerned, and nothing left under a final output name
// or a .tmp-* name in the output directory, whose earlier content survives.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cli_util.h"
#include "perclod/outputs.h"

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
  bool busy = false;               // run while another command holds {O} (OutputDirectoryLock)
};

std::string expand(std::string s, const Fixture& f) {
  for (auto [key, value] : {std::pair{std::string("{D}"), f.dir.string()}, std::pair{std::string("{O}"), f.out.string()}})
    for (size_t at; (at = s.find(key)) != std::string::npos;) s.replace(at, key.size(), value);
  return s;
}

// Issue 56's catalogue: CityJSON read strictly, batches whose model names
// clash with the batch's own files, display profiles too small or too
// narrow, distances and models too large for float.
void add_issue56_files(const Fixture& f) {
  const std::string tri = R"("t": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": "2",
      "boundaries": [[[0, 1, 2]]]}]})";
  auto city = [&](const std::string& version, const std::string& extra, const std::string& vertices) {
    return R"({"type": "CityJSON", "version": ")" + version + R"(", )" + extra + R"("CityObjects": {)" + tri +
           R"(}, "vertices": [)" + vertices + "]}";
  };
  const std::string ok = "[0, 0, 0], [1, 0, 0], [0, 1, 0]";
  // One vertex nested 100,000 arrays deep: rendering it in the error overflowed the stack.
  f.file("deep.city.json", city("2.0", "", std::string(100000, '[') + std::string(100000, ']')));
  f.file("v99.city.json", city("99.0", "", ok));
  f.file("v06.city.json", city("0.6", "", ok));
  f.file("scale0.city.json", city("1.1", R"("transform": {"scale": [0, 0, 0], "translate": [0, 0, 0]}, )", ok));
  f.file("scale0.yaml", "model: scale0.city.json\ndisplay: display.yaml\ndistances: [56]\nout: " +
                            f.out.string() + "\n");
  // Batches: one of the cube (run while its folder is busy), and model files
  // named like the batch's own files.
  const std::string batch = "display: display.yaml\ndistances: [56]\nout: " + f.out.string() + "\nmodels:\n";
  f.file("batch.yaml", batch + "  - cube.obj\n");
  for (const std::string name : {"index.html", "tileset.json", "batch_0_of_1.json"}) {
    f.file(name + ".obj", kCube);
    f.file("reserved-" + name + ".yaml", batch + "  - cube.obj\n  - " + name + ".obj\n");
  }
  // Display profiles: too small, too narrow.
  const std::string screen = "dpi: 86.27\nviewer_distance_m: 0.5\n";
  f.file("display-2px-wide.yaml", "width: 2\nheight: 64\n" + screen);
  f.file("display-1px-high.yaml", "width: 96\nheight: 1\n" + screen);
  f.file("display-7x5.yaml", "width: 7\nheight: 5\n" + screen);
  f.file("display-dpi.yaml", "width: 96\nheight: 64\ndpi: 1e12\nviewer_distance_m: 0.5\n");
  f.file("display-far.yaml", "width: 96\nheight: 64\ndpi: 86.27\nviewer_distance_m: 1e9\n");
  f.file("display-tall.yaml", "width: 16\nheight: 16384\n" + screen);
  f.file("far-viewer.yaml", "model: cube.obj\ndisplay: display-far.yaml\ndistances: [56]\nout: " +
                                f.out.string() + "\n");
  // Too large for float: a distance, a model.
  f.file("far.yaml", "model: cube.obj\ndistances: [56, 1e300]\nout: " + f.out.string() + "\n");
  // The cube 2e30 m across.
  std::string huge = "v -1e30 -1e30 0\nv 1e30 -1e30 0\nv 1e30 1e30 0\nv -1e30 1e30 0\n"
                     "v -1e30 -1e30 2e30\nv 1e30 -1e30 2e30\nv 1e30 1e30 2e30\nv -1e30 1e30 2e30\n";
  huge += kCube.substr(kCube.find("f "));
  f.file("huge.obj", huge);
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
  add_issue56_files(f);
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
      // Issue 56. 1: a crash rendering a deeply nested value in the error.
      {"info_cityjson_nested_100000_deep", "info {D}/deep.city.json", 1,
       {"{D}/deep.city.json: vertex 0 is [[[[", "not 3 numbers"}},
      // 2: a second run of a batch while the first holds its folder.
      {"run_batch_while_it_runs", "run {D}/batch.yaml", 1,
       {"{O}: another perclod command is writing to this directory"}, true},
      {"run_batch_force_while_it_runs", "run {D}/batch.yaml --force", 1, {"{O}: another perclod command"}, true},
      // 3: model names clashing with the batch's own files, before any work.
      {"run_batch_model_named_index_html", "run {D}/reserved-index.html.yaml", 1,
       {"{D}/reserved-index.html.yaml: models[1]", "'{O}/index.html'", "rename the model file"}},
      {"run_batch_model_named_tileset_json", "run {D}/reserved-tileset.json.yaml", 1,
       {"{D}/reserved-tileset.json.yaml: models[1]", "'{O}/tileset.json'"}},
      {"run_batch_model_named_batch_0_of_1", "run {D}/reserved-batch_0_of_1.json.yaml", 1,
       {"{D}/reserved-batch_0_of_1.json.yaml: models[1]", "'{O}/batch_0_of_1.json'"}},
      // 4: CityJSON read strictly.
      {"info_cityjson_version_99", "info {D}/v99.city.json", 1,
       {"{D}/v99.city.json: CityJSON version \"99.0\" is not supported"}},
      {"info_cityjson_version_0_6", "info {D}/v06.city.json", 1,
       {"{D}/v06.city.json: CityJSON version \"0.6\" is not supported"}},
      {"info_cityjson_zero_scale", "info {D}/scale0.city.json", 1,
       {"{D}/scale0.city.json: \"transform\" \"scale\" is [0,0,0]"}},
      {"run_cityjson_zero_scale", "run {D}/scale0.yaml", 1, {"{D}/scale0.city.json: \"transform\" \"scale\""}},
      // 5: errors that blame the display profile, not the model or the eye.
      {"render_display_2px_wide", "render {D}/cube.obj -d 56 --display {D}/display-2px-wide.yaml -o {O}", 1,
       {"{D}/display-2px-wide.yaml: 'width' must be 16..16384 pixels, not 2"}},
      {"render_display_1px_high", "render {D}/cube.obj -d 56 --display {D}/display-1px-high.yaml -o {O}", 1,
       {"{D}/display-1px-high.yaml: 'height' must be 16..16384 pixels, not 1"}},
      {"label_display_7x5", "label {D}/cube.obj -d 56 --display {D}/display-7x5.yaml -o {O}", 1,
       {"{D}/display-7x5.yaml: 'width'"}},
      {"render_display_dpi_1e12", "render {D}/cube.obj -d 56 --display {D}/display-dpi.yaml -o {O}", 1,
       {"{D}/display-dpi.yaml: the field of view is", "'dpi' 1e+12", "1 to 179 degrees"}},
      {"run_display_viewer_1e9_m", "run {D}/far-viewer.yaml", 1,
       {"{D}/display-far.yaml: the field of view is", "'viewer_distance_m' 1e+09"}},
      {"render_display_too_narrow", "render {D}/cube.obj -d 56 --display {D}/display-tall.yaml -o {O}", 1,
       {"{D}/display-tall.yaml: the field of view is", "degrees wide ('width' 16 px"}},
      // 5: a distance or a model too large for float: an error about that value.
      {"render_distance_1e300", "render {D}/cube.obj -d 1e300 -o {O}", 1,
       {"--distance: 1e+300 m is farther than the 1e+08 m perclod takes"}},
      {"run_distance_1e300", "run {D}/far.yaml", 1, {"{D}/far.yaml: 'distances': 1e+300 m is farther"}},
      {"info_model_2e30_m", "info {D}/huge.obj", 1, {"{D}/huge.obj: the model spans 2e+30 m, more than the 1e+08 m"}},
      {"label_model_2e30_m", "label {D}/huge.obj -d 56 -o {O}", 1, {"{D}/huge.obj: the model spans 2e+30 m"}},
      {"render_model_scaled_to_1e30_m", "render {D}/cube.obj --scale 1e30 -d 56 -o {O}", 1,
       {"{D}/cube.obj: the model spans 2e+30 m after the unit scale 1e+30"}},
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
    std::optional<perclod::OutputDirectoryLock> busy;
    if (c.busy) busy.emplace(f.out.string());
    auto r = run_cli(expand(c.args, f));
    busy.reset();
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
    for (const auto& e : fs::recursive_directory_iterator(f.out))
      if (e.path().filename() != perclod::kLockFile)  // stays, empty: deleted it could be held twice
        left.push_back(e.path().filename().string());
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
