// Georeferencing with PROJ (perclod/crs.h, model_crs_frame, crs_transform):
// the written forms of an EPSG code, the CRSs refused and why, the local
// frame's geometry, the `crs` setting, and the CRS a CityJSON file states.
// The Delft 3D BAG tile against cs2cs is in tests/e2e/test_crs_delft.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "perclod/config.h"
#include "perclod/crs.h"
#include "perclod/model_exports.h"
#include "test_util.h"

using namespace perclod;

namespace {
using test::error_of;
using test::has;
using Vec = std::array<double, 3>;

// A point of the Delft 3D BAG tile (EPSG:7415: RD New + NAP height): the
// centre of its metadata.geographicalExtent.
constexpr Vec kDelft = {85320.01450317382, 446656.4804855652, 24.987579226493835};

double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const Vec& a) { return std::sqrt(dot(a, a)); }
Vec unit(const Vec& a) {
  const double n = norm(a);
  return {a[0] / n, a[1] / n, a[2] / n};
}

// The WGS84 ellipsoid's normal, east and north at a latitude and longitude.
Vec ellipsoid_normal(double lat_deg, double lon_deg) {
  const double la = lat_deg * M_PI / 180, lo = lon_deg * M_PI / 180;
  return {std::cos(la) * std::cos(lo), std::cos(la) * std::sin(lo), std::sin(la)};
}
Vec true_east(double lon_deg) {
  const double lo = lon_deg * M_PI / 180;
  return {-std::sin(lo), std::cos(lo), 0};
}

// M (column-major 4x4) times (p, 1).
Vec at_point(const std::array<double, 16>& m, const Vec& p) {
  Vec r;
  for (int a = 0; a < 3; ++a) r[a] = m[a] * p[0] + m[4 + a] * p[1] + m[8 + a] * p[2] + m[12 + a];
  return r;
}

}  // namespace

TEST(Crs, EpsgCodeReadsTheWrittenForms) {
  for (const char* s : {"EPSG:7415", "epsg:7415", "7415", " EPSG:7415 ", "urn:ogc:def:crs:EPSG::7415",
                        "urn:ogc:def:crs:EPSG:9.8.6:7415", "https://www.opengis.net/def/crs/EPSG/0/7415",
                        "http://www.opengis.net/def/crs/EPSG/0/7415"})
    EXPECT_EQ(epsg_code(s), "EPSG:7415") << s;
  for (const char* s : {"", "EPSG:", "EPSG:74a5", "EPSG::7415", "urn:ogc:def:crs:OGC:1.3:CRS84", "RD New",
                        "https://example.com/def/crs/EPSG/0/7415", "urn:ogc:def:crs:EPSG:x:7415", "-7415"})
    EXPECT_EQ(epsg_code(s), "") << s;
}

// Projected, compound and geocentric CRSs pass; an unknown code and CRSs
// whose coordinates are not metres on the Earth are refused, naming the code.
TEST(Crs, CheckRefusesUnknownCodesAndCrsWithoutMetres) {
  for (const char* ok : {"EPSG:7415", "EPSG:28992", "EPSG:32632", "EPSG:2056", "EPSG:4978", "urn:ogc:def:crs:EPSG::25832"})
    EXPECT_EQ(error_of([&] { check_crs(ok); }), "") << ok;
  const std::string unknown = error_of([] { check_crs("EPSG:999999"); });
  EXPECT_TRUE(has(unknown, "EPSG:999999 is not a CRS PROJ knows")) << unknown;
  EXPECT_TRUE(has(error_of([] { check_crs("EPSG:4326"); }), "EPSG:4326 (WGS 84) is a geographic CRS, in degrees"));
  EXPECT_TRUE(has(error_of([] { check_crs("EPSG:5709"); }), "is a vertical CRS"));  // NAP height alone
  EXPECT_TRUE(has(error_of([] { check_crs("RD New"); }), "'RD New' is not an EPSG code"));
  // Remembered: the same answer again.
  EXPECT_EQ(error_of([] { check_crs("EPSG:999999"); }), unknown);
}

// The frame at Delft: up is the ellipsoid's normal with unit length (NAP
// heights are metres); east and north are orthogonal, of one length (RD is
// conformal) within 1e-4 of 1 (its scale factor), and turned from true east
// by RD's grid convergence there (about -0.8 degrees: west of RD's central
// meridian, 5.39 E). The position is RD New's own transformation's
// (Amersfoort to WGS 84 (4), 1 m), not the ballpark geographic offset PROJ
// 9.1 ranks first for EPSG:7415 as a whole without the NSGI grids (110 m off).
TEST(Crs, FrameHonoursTheProjectionsScaleAndConvergence) {
  const CrsFrame f = crs_frame("EPSG:7415", kDelft);
  EXPECT_EQ(f.code, "EPSG:7415");
  EXPECT_EQ(f.name, "Amersfoort / RD New + NAP height");
  EXPECT_NEAR(f.lat, 52.0039022, 1e-6);  // cs2cs -d 9 EPSG:28992 EPSG:4979: 52.003902169 4.372413486
  EXPECT_NEAR(f.lon, 4.3724135, 1e-6);
  EXPECT_FALSE(f.ballpark) << f.operation;
  EXPECT_EQ(f.accuracy_m, 1) << f.operation;
  const Vec& east = f.axes[0];
  const Vec& north = f.axes[1];
  const Vec& up = f.axes[2];
  const Vec normal = ellipsoid_normal(f.lat, f.lon);
  EXPECT_NEAR(norm(up), 1.0, 1e-6);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(unit(up)[a], normal[a], 1e-6) << a;
  EXPECT_NEAR(dot(unit(east), unit(north)), 0, 1e-6);
  // Heights above a geoid (EGM96 here) tilt east and north by its slope, the
  // deflection of the vertical: 4e-6 and 9e-6 rad at Delft (3 mm over 300 m).
  EXPECT_NEAR(dot(unit(east), unit(up)), 0, 2e-5);
  EXPECT_NEAR(dot(unit(north), unit(up)), 0, 2e-5);
  EXPECT_NEAR(norm(east), norm(north), 1e-6);
  EXPECT_NEAR(norm(east), 1.0, 1e-4);
  const Vec e = true_east(f.lon);
  const double convergence = std::atan2(dot(unit(east), {normal[1] * e[2] - normal[2] * e[1],
                                                         normal[2] * e[0] - normal[0] * e[2],
                                                         normal[0] * e[1] - normal[1] * e[0]}),
                                        dot(unit(east), e)) * 180 / M_PI;
  EXPECT_GT(std::abs(convergence), 0.6) << convergence;
  EXPECT_LT(std::abs(convergence), 1.0) << convergence;
  // The Earth-centred origin is the WGS84 position's (the two PROJ paths agree).
  const auto enu = enu_to_ecef(f.lat, f.lon, f.height);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(f.origin[a], enu[12 + a], 1e-3) << a;
}

// Heights: a compound CRS's go through its own transformation (recorded); a
// 2D projected CRS's z is taken as an ellipsoidal height as it is; a
// geocentric CRS's are its own.
TEST(Crs, FrameSaysHowHeightsWereTaken) {
  const CrsFrame rd = crs_frame("EPSG:7415", kDelft);
  EXPECT_TRUE(has(rd.height_operation, "NAP height")) << rd.height_operation;
  // NAP heights are about 43.5 m over the WGS84 ellipsoid at Delft: by the
  // NAP geoid when PROJ has its grid, else by EGM96 (Debian's proj-data),
  // never as ellipsoidal heights.
  EXPECT_FALSE(rd.height_ballpark);
  EXPECT_NEAR(rd.height - kDelft[2], 43.5, 1.0);
  if (rd.height_fallback == "EGM96") {
    EXPECT_NEAR(rd.height - kDelft[2], 43.469, 0.01);
  }
  const CrsFrame utm = crs_frame("EPSG:32632", {678117.251, 5403764.2575, 421.24});
  EXPECT_TRUE(utm.height_ballpark);
  EXPECT_EQ(utm.height_operation, "");
  EXPECT_NEAR(utm.height, 421.24, 1e-6);
  const auto enu = enu_to_ecef(utm.lat, utm.lon, utm.height);
  const CrsFrame ecef = crs_frame("EPSG:4978", {enu[12], enu[13], enu[14]});
  EXPECT_FALSE(ecef.height_ballpark);
  EXPECT_NEAR(ecef.lat, utm.lat, 1e-9);
  EXPECT_NEAR(ecef.height, 421.24, 1e-6);
  for (int i = 0; i < 3; ++i)
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(ecef.axes[i][r], i == r, 1e-9);  // ECEF to ECEF: the identity
}

// The transform takes the tileset's coordinates (source, +Z up; a Y-up
// source turned as to_tiles_frame turns it) to ECEF: the centre to the
// frame's origin, any point p to origin + J (p - centre).
TEST(Crs, TransformMapsTilesetCoordinatesToEcef) {
  const CrsFrame f = crs_frame("EPSG:7415", kDelft);
  const Vec p = {kDelft[0] + 120, kDelft[1] - 80, kDelft[2] + 15};
  Vec want = f.origin;
  for (int i = 0; i < 3; ++i)
    for (int r = 0; r < 3; ++r) want[r] += f.axes[i][r] * (p[i] - kDelft[i]);
  const auto mz = crs_transform(f, kDelft, UpAxis::Z);
  const auto my = crs_transform(f, kDelft, UpAxis::Y);
  const Vec got_z = at_point(mz, p), got_y = at_point(my, {p[0], -p[2], p[1]});
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(at_point(mz, kDelft)[a], f.origin[a], 1e-6);
    EXPECT_NEAR(got_z[a], want[a], 1e-6) << a;
    EXPECT_NEAR(got_y[a], want[a], 1e-6) << a;
  }
  EXPECT_EQ(mz[15], 1);
  EXPECT_EQ(mz[3], 0);
  // A model in millimetres (scale 0.001): the same place, a thousandth the axes.
  const CrsFrame mm = crs_frame("EPSG:7415", {kDelft[0] * 0.001, kDelft[1] * 0.001, kDelft[2] * 0.001}, 0.001);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(mm.axes[0][a], f.axes[0][a] * 1000, 1e-3);
}

// The CRS of a model: the config's, else its file's; none with crs: none or
// crs_origin. A file's reference system that is no EPSG code, or a code PROJ
// does not know, fails naming the model file and the code.
TEST(Crs, ModelFrameTakesTheFilesCrsUnlessTheConfigSaysOtherwise) {
  Scene scene = test::box();
  scene.offset = kDelft;
  BatchConfig c;
  c.model = "tile.city.json";
  LoadReport load;
  EXPECT_FALSE(model_crs_frame(c, load, scene));  // no CRS anywhere: source coordinates
  load.reference_system = "urn:ogc:def:crs:EPSG::7415";
  ASSERT_TRUE(model_crs_frame(c, load, scene));
  EXPECT_EQ(model_crs_frame(c, load, scene)->code, "EPSG:7415");
  c.crs = "EPSG:28992";
  EXPECT_EQ(model_crs_frame(c, load, scene)->code, "EPSG:28992");
  c.crs = "none";
  EXPECT_FALSE(model_crs_frame(c, load, scene));
  c.crs = "";
  c.crs_origin = true;
  EXPECT_FALSE(model_crs_frame(c, load, scene));
  c.crs_origin = false;
  load.reference_system = "EPSG:999999";
  std::string err = error_of([&] { model_crs_frame(c, load, scene); });
  EXPECT_TRUE(has(err, "tile.city.json: its metadata.referenceSystem 'EPSG:999999': EPSG:999999 is not a CRS")) << err;
  load.reference_system = "urn:ogc:def:crs:OGC:1.3:CRS84";
  err = error_of([&] { model_crs_frame(c, load, scene); });
  EXPECT_TRUE(has(err, "tile.city.json: its metadata.referenceSystem 'urn:ogc:def:crs:OGC:1.3:CRS84' is no EPSG code"))
      << err;
}

// The loader reports a CityJSON file's referenceSystem as written.
TEST(Crs, CityJsonLoaderReportsTheReferenceSystem) {
  LoadReport rep;
  load_scene(std::string(PERCLOD_SOURCE_DIR) + "/tests/pipeline/fixtures/bldg_4018215.city.json", {}, &rep);
  EXPECT_EQ(rep.reference_system, "https://www.opengis.net/def/crs/EPSG/0/32632");
  EXPECT_EQ(load_report_json(rep)["reference_system"], rep.reference_system);
  load_scene(std::string(PERCLOD_SOURCE_DIR) + "/data/ingolstadt/bldg_4018215.obj", {}, &rep);
  EXPECT_EQ(rep.reference_system, "");
  EXPECT_FALSE(load_report_json(rep).contains("reference_system"));
}

// `crs` in a config: every written form, or none; an unknown code and crs
// with crs_origin are refused naming the file (and the code).
TEST(Crs, ConfigReadsCrsAndRefusesBadCodesAndCrsWithCrsOrigin) {
  test::TempDir dir("crs-config");
  dir.file("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const auto load = [&](const std::string& yaml) {
    return load_batch_config(dir.file("c.yaml", "model: m.obj\ndistances: [10]\n" + yaml));
  };
  for (const char* form : {"EPSG:7415", "7415", "urn:ogc:def:crs:EPSG::7415", "https://www.opengis.net/def/crs/EPSG/0/7415"})
    EXPECT_EQ(load(std::string("crs: ") + form + "\n").crs, "EPSG:7415") << form;
  EXPECT_EQ(load("crs: none\n").crs, "none");
  EXPECT_EQ(load("").crs, "");
  // Configs without crs hash as before the key existed.
  EXPECT_FALSE(settings_json(load("")).contains("crs"));
  EXPECT_EQ(settings_json(load("crs: 7415\n"))["crs"], "EPSG:7415");
  const std::string cfg = dir / "c.yaml";
  std::string err = error_of([&] { load("crs: EPSG:999999\n"); });
  EXPECT_EQ(err.rfind(cfg + ": 'crs': EPSG:999999 is not a CRS PROJ knows", 0), 0u) << err;
  err = error_of([&] { load("crs: EPSG:4326\n"); });
  EXPECT_TRUE(has(err, "geographic CRS")) << err;
  err = error_of([&] { load("crs: EPSG:7415\ncrs_origin: {lat: 52, lon: 4.4}\n"); });
  EXPECT_EQ(err, cfg + ": give 'crs' (the model's CRS) or 'crs_origin' (a WGS84 point), not both");
  err = error_of([&] { load("crs: [7415]\n"); });
  EXPECT_TRUE(has(err, "'crs' must be an EPSG code")) << err;
  // In a batch, a top-level crs_origin and an entry's crs meet in the entry.
  err = error_of([&] {
    load_config_file(dir.file("b.yaml", "distances: [10]\ncrs_origin: {lat: 52, lon: 4.4}\n"
                                        "models:\n  - {model: m.obj, crs: EPSG:7415}\n"));
  });
  EXPECT_TRUE(has(err, "b.yaml: models[0]: give 'crs'")) << err;
}
