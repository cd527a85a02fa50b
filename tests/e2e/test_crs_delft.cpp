// Georeferencing end to end: the Delft 3D BAG tile (../shared/data, EPSG:7415)
// lands where PROJ's cs2cs puts it, `perclod run` places a CityJSON file by
// the CRS it states, and unknown codes stop a run before any work, naming
// the file and the code. The frame's own geometry is tests/pipeline/test_crs.cpp's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_util.h"
#include "perclod/load.h"
#include "perclod/model_exports.h"

using namespace perclod;
using perclod::test::run_cli;
namespace fs = std::filesystem;

namespace {

using Vec = std::array<double, 3>;
const std::string kDelft = std::string(PERCLOD_SHARED_DATA) + "/cityjson/3dbag_5910_delft.city.json";

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

// The first line cs2cs prints for `p` (three numbers), or false when cs2cs
// is not installed.
bool cs2cs(const std::string& from, const std::string& to, const Vec& p, Vec& out) {
  if (!fs::exists("/usr/bin/cs2cs")) return false;
  std::ostringstream cmd;
  cmd.precision(17);
  cmd << "echo " << p[0] << " " << p[1] << " " << p[2] << " | /usr/bin/cs2cs -d 9 " << from << " " << to;
  FILE* f = popen(cmd.str().c_str(), "r");
  if (!f) return false;
  char buf[256] = {0};
  const bool read = fgets(buf, sizeof buf - 1, f) != nullptr;
  pclose(f);
  return read && std::sscanf(buf, "%lf %lf %lf", &out[0], &out[1], &out[2]) == 3;
}

// Where PROJ puts `p` of EPSG:7415 (latitude, longitude, ellipsoidal
// height), as perclod asks it: the position by RD New's own transformation
// (EPSG:28992, the horizontal part), the height by EPSG:7415's.
bool cs2cs_wgs84(const Vec& p, Vec& lat_lon_h) {
  Vec height;
  if (!cs2cs("EPSG:28992", "EPSG:4979", p, lat_lon_h) || !cs2cs("EPSG:7415", "EPSG:4979", p, height)) return false;
  lat_lon_h[2] = height[2];
  // Without the NAP geoid grid PROJ passes the height through (a ballpark
  // step); perclod then takes it as an EGM96 height: so does the reference.
  Vec egm96;
  if (std::abs(height[2] - p[2]) < 1e-6 && cs2cs("EPSG:4326+5773", "EPSG:4979", {lat_lon_h[0], lat_lon_h[1], p[2]}, egm96))
    lat_lon_h[2] = egm96[2];
  return true;
}

Vec ecef_of(double lat, double lon, double height) {
  const auto m = enu_to_ecef(lat, lon, height);
  return {m[12], m[13], m[14]};
}

Vec at_point(const std::array<double, 16>& m, const Vec& p) {
  Vec r;
  for (int a = 0; a < 3; ++a) r[a] = m[a] * p[0] + m[4 + a] * p[1] + m[8 + a] * p[2] + m[12 + a];
  return r;
}

double distance(const Vec& a, const Vec& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

}  // namespace

// The tile's extent centre (metadata.geographicalExtent) through the
// tileset's transform lands within 1 m of where cs2cs puts it. The
// reference, computed once (PROJ 9.1.1, Debian 12's proj-data):
//
//   echo 85320.01450317382 446656.4804855652 24.987579226493835 | cs2cs -d 9 EPSG:28992 EPSG:4979
//   52.003902169  4.372413486  24.987579226
//   echo 52.003902169 4.372413486 24.987579226 | cs2cs -d 9 EPSG:4326+5773 EPSG:4979
//   52.003902169  4.372413486  68.456908150     (the NAP height as an EGM96 one)
//
// EPSG:28992 is EPSG:7415's horizontal part (RD New): PROJ takes "Amersfoort
// to WGS 84 (4)", a Helmert shift good to 1 m. For EPSG:7415 as a whole
// (cs2cs EPSG:7415 EPSG:4979: 52.004870624 4.372700644 24.987579226) it
// ranks first a ballpark geographic offset, 109.5 m from it, because
// proj-data lacks the NSGI grids (nl_nsgi_rdtrans2018.tif,
// nl_nsgi_nlgeo2018.tif); the height is EPSG:7415's, or without
// nl_nsgi_nlgeo2018.tif the NAP height taken as a height above the EGM96
// geoid (docs/usage.md#export-for-viewers). cs2cs is asked again when it
// is installed, so the test follows the grids PROJ has.
TEST(CrsDelft, ExtentCentreLandsWithinAMetreOfCs2cs) {
  if (!fs::exists(kDelft)) GTEST_SKIP() << kDelft << " is not there";
  LoadReport rep;
  const Scene scene = load_scene(kDelft, {}, &rep);
  EXPECT_EQ(rep.reference_system, "urn:ogc:def:crs:EPSG::7415");
  BatchConfig c;  // no crs: the file's
  c.model = kDelft;
  c.up = UpAxis::Z;
  const std::optional<CrsFrame> frame = model_crs_frame(c, rep, scene);
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->code, "EPSG:7415");
  const auto m = crs_transform(*frame, scene.offset, c.up);

  std::ifstream in(kDelft);
  const auto extent = nlohmann::json::parse(in)["metadata"]["geographicalExtent"];
  Vec centre;
  for (int a = 0; a < 3; ++a) centre[a] = 0.5 * (extent[a].get<double>() + extent[a + 3].get<double>());
  Vec ref = {52.003902169, 4.372413486, 68.456908150};
  const bool live = cs2cs_wgs84(centre, ref);
  const double d = distance(at_point(m, centre), ecef_of(ref[0], ref[1], ref[2]));
  std::printf("Delft extent centre: transform vs cs2cs (%s): %.4f m\n", live ? "run now" : "recorded", d);
  EXPECT_LT(d, 1.0);
  // The frame's own point, the bounding-box centre, is PROJ's exactly.
  if (cs2cs_wgs84(scene.offset, ref)) {
    EXPECT_NEAR(frame->lat, ref[0], 1e-8);
    EXPECT_NEAR(frame->lon, ref[1], 1e-8);
    EXPECT_NEAR(frame->height, ref[2], 1e-3);
  }
}

// `perclod run` on the Delft tile without a `crs` in the config takes
// EPSG:7415 from the file: the manifest says so, and the tileset's transform
// takes the root box's centre (the bounding-box centre, 85320.0145
// 446656.4805 24.9875) within 1 m of where cs2cs puts it (recorded: cs2cs -d 9
// EPSG:28992 EPSG:4979 gives 52.003902169 4.372413486; the height is
// the NAP height over EGM96, 68.4569, as above). Cheap settings: one distance, one view (8 s).
TEST(CrsDelft, RunWithoutCrsTakesEpsg7415FromTheFile) {
  if (!fs::exists(kDelft)) GTEST_SKIP() << kDelft << " is not there";
  const fs::path root = test::fresh_dir("crs-delft", true);
  std::ofstream(root / "small.yaml") << "width: 320\nheight: 256\ndpi: 21.5675\nviewer_distance_m: 0.5\n";
  std::ofstream(root / "run.yaml") << "model: " << kDelft << "\nout: " << (root / "out").string() << "\nup: z\n"
                                   << "distances: [427]\nviews: top\nsamples: 1\njudge_views: none\n"
                                   << "simplify: cluster\ndebug_images: false\ndisplay: small.yaml\n";
  const auto r = run_cli("run " + (root / "run.yaml").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto manifest = read_json(root / "out" / "3dbag_5910_delft_manifest.json");
  const auto& crs = manifest["crs"];
  EXPECT_EQ(crs["code"], "EPSG:7415");
  EXPECT_EQ(crs["from"], "model file");
  EXPECT_TRUE(crs["heights_as_ellipsoidal"].is_boolean());  // true without the NAP geoid grid
  EXPECT_FALSE(manifest["config"]["settings"].contains("crs"));
  const auto tile = read_json(root / "out" / "3dbag_5910_delft_tileset.json")["root"];
  ASSERT_TRUE(tile.contains("transform"));
  std::array<double, 16> m;
  for (int k = 0; k < 16; ++k) m[k] = tile["transform"][k].get<double>();
  const auto& box = tile["boundingVolume"]["box"];
  const Vec centre = {box[0].get<double>(), box[1].get<double>(), box[2].get<double>()};
  Vec ref = {52.003902169, 4.372413486, 68.4569};
  cs2cs_wgs84(centre, ref);
  const double d = distance(at_point(m, centre), ecef_of(ref[0], ref[1], ref[2]));
  std::printf("Delft run: root box centre vs cs2cs: %.4f m\n", d);
  EXPECT_LT(d, 1.0);
  EXPECT_NEAR(crs["wgs84"]["lat"].get<double>(), ref[0], 1e-7);
  EXPECT_NEAR(crs["wgs84"]["lon"].get<double>(), ref[1], 1e-7);
  fs::remove_all(root);
}

// `perclod run` without a `crs` places a CityJSON file by its
// referenceSystem (the fixture's EPSG:32632): the manifest records the code,
// where it came from and the centre's WGS84 position, and the tileset's
// transform takes the box centre there.
TEST(CrsCli, RunPlacesACityJsonFileByItsOwnCrs) {
  const fs::path root = test::fresh_dir("crs-run", true);
  std::ofstream(root / "small.yaml") << "width: 320\nheight: 256\ndpi: 21.5675\nviewer_distance_m: 0.5\n";
  std::ofstream(root / "run.yaml") << "model: " PERCLOD_SOURCE_DIR "/tests/pipeline/fixtures/bldg_4018215.city.json\n"
                                   << "out: " << (root / "out").string() << "\nup: z\ncityjson_lod: \"2\"\n"
                                   << "distances: [56]\nviews: facades\nsamples: 1\njudge_views: none\n"
                                   << "display: small.yaml\n";
  const auto r = run_cli("run " + (root / "run.yaml").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto manifest = read_json(root / "out" / "bldg_4018215_manifest.json");
  const auto& crs = manifest["crs"];
  EXPECT_EQ(crs["code"], "EPSG:32632");
  EXPECT_EQ(crs["from"], "model file");
  EXPECT_NEAR(crs["wgs84"]["lat"].get<double>(), 48.76, 0.01);
  EXPECT_NEAR(crs["wgs84"]["lon"].get<double>(), 11.42, 0.01);
  EXPECT_FALSE(manifest["config"]["settings"].contains("crs"));
  const auto tileset = read_json(root / "out" / "bldg_4018215_tileset.json");
  const auto& root_tile = tileset["root"];
  ASSERT_TRUE(root_tile.contains("transform"));
  std::array<double, 16> m;
  for (int k = 0; k < 16; ++k) m[k] = root_tile["transform"][k].get<double>();
  const auto& box = root_tile["boundingVolume"]["box"];
  const Vec at = at_point(m, {box[0].get<double>(), box[1].get<double>(), box[2].get<double>()});
  const auto& w = crs["wgs84"];
  EXPECT_LT(distance(at, ecef_of(w["lat"].get<double>(), w["lon"].get<double>(), w["height"].get<double>())), 1e-3);
  fs::remove_all(root);
}

// An unknown code stops the run with exit status 1 before any LOD work,
// naming the file it came from: the config's crs, or a model file's
// referenceSystem.
TEST(CrsCli, UnknownCodesStopTheRunNamingTheFile) {
  const fs::path root = test::fresh_dir("crs-unknown", true);
  std::ofstream(root / "tri.city.json")
      << R"({"type": "CityJSON", "version": "1.1", "transform": {"scale": [1, 1, 1], "translate": [0, 0, 0]},)"
      << R"( "metadata": {"referenceSystem": "https://www.opengis.net/def/crs/EPSG/0/999999"},)"
      << R"( "CityObjects": {"b": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": "2",)"
      << R"( "boundaries": [[[0, 1, 2]]]}]}}, "vertices": [[0, 0, 0], [10, 0, 0], [0, 10, 5]]})";
  const std::string settings = "distances: [56]\nviews: top\nsamples: 1\njudge_views: none\nup: z\n";
  std::ofstream(root / "config.yaml") << "model: tri.city.json\ncrs: EPSG:999999\n" << settings;
  std::ofstream(root / "file.yaml") << "model: tri.city.json\nout: " << (root / "out").string() << "\n" << settings;
  auto r = run_cli("run " + (root / "config.yaml").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find((root / "config.yaml").string() + ": 'crs': EPSG:999999 is not a CRS PROJ knows"),
            std::string::npos)
      << r.err;
  r = run_cli("run " + (root / "file.yaml").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("tri.city.json: its metadata.referenceSystem"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("EPSG:999999 is not a CRS PROJ knows"), std::string::npos) << r.err;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(root / "out", ec))  // nothing labelled or simplified
    EXPECT_EQ(e.path().filename().string().find("56m"), std::string::npos) << e.path();
  fs::remove_all(root);
}
