// Display profiles, facade and free views, and config errors. The camera
// itself (one definition for renderer and ray caster) is tested with the
// scene types, in raycast/scene/test_camera.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "perclod/camera.h"
#include "perclod/config.h"
#include "perclod/views.h"

using namespace perclod;

TEST(Display, PaperProfileGivesThePapersNumbers) {
  DisplayProfile d = load_display_profile(PERCLOD_SOURCE_DIR "/configs/displays/paper-19in.yaml");
  EXPECT_EQ(d.width, 1280);
  EXPECT_EQ(d.height, 1024);
  EXPECT_NEAR(d.pixels_per_degree(), 29.64, 0.01);
  EXPECT_NEAR(d.f_max(), 14.82, 0.01);
  EXPECT_NEAR(d.natural_fov_y() * 180 / M_PI, 33.56, 0.01);  // Zhu et al. print 33.5
  Camera c = look_at({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, d.fov_y(), d.width, d.height, 1, 10);
  // One pixel is the same visual angle on screen and in the scene: 1/ppd degrees at the centre.
  double px_angle = std::atan(c.pixel_footprint(1.0)) * 180 / M_PI;
  EXPECT_NEAR(px_angle, 1.0 / d.pixels_per_degree(), 1e-3 / d.pixels_per_degree());
}

TEST(Views, FacadeEyeStandsOnTheAxisInFrontOfTheFace) {
  Bounds b;
  b.lo = {-10, -4, 0};
  b.hi = {10, 4, 12};
  DisplayProfile d;
  Camera c = facade_camera(b, UpAxis::Z, "-y", 56, d);
  EXPECT_NEAR(c.eye.x(), 0, 1e-9);
  EXPECT_NEAR(c.eye.y(), -4 - 56, 1e-9);
  EXPECT_NEAR(c.eye.z(), 6, 1e-9);
  EXPECT_NEAR(c.forward.y(), 1, 1e-12);
  EXPECT_NEAR(c.up.z(), 1, 1e-12);
  EXPECT_LE(c.znear, 56.0);   // the nearest face is at depth 56
  EXPECT_GE(c.zfar, 64.0);    // the back face at 64
  Camera e = facade_camera(b, UpAxis::Z, "+x", 10, d);
  EXPECT_NEAR(e.eye.x(), 20, 1e-9);
  EXPECT_NEAR(e.forward.x(), -1, 1e-12);
}

TEST(Views, FacadeNamesFollowTheUpAxis) {
  EXPECT_EQ(parse_facades("all", UpAxis::Z), (std::vector<std::string>{"+x", "-x", "+y", "-y"}));
  EXPECT_EQ(parse_facades("all", UpAxis::Y), (std::vector<std::string>{"+x", "-x", "+z", "-z"}));
  EXPECT_EQ(parse_facades("+x,-y", UpAxis::Z), (std::vector<std::string>{"+x", "-y"}));
  EXPECT_THROW(parse_facades("+z", UpAxis::Z), std::invalid_argument);  // the up axis is no facade
  EXPECT_THROW(parse_facades("north", UpAxis::Z), std::invalid_argument);
  EXPECT_EQ(parse_facades("az30el15,-x", UpAxis::Z), (std::vector<std::string>{"az30el15", "-x"}));
  EXPECT_THROW(parse_facades("az30el95", UpAxis::Z), std::invalid_argument);
  EXPECT_THROW(parse_facades("az30", UpAxis::Z), std::invalid_argument);
}

TEST(Views, FreeViewLooksAtTheCentreFromAzimuthAndElevation) {
  Bounds b;
  b.lo = {-3, -4, 0};
  b.hi = {3, 4, 10};  // centre (0, 0, 5), half diagonal sqrt(9 + 16 + 25) = 7.07
  DisplayProfile d;
  Camera c = facade_camera(b, UpAxis::Z, "az90el30", 20, d);
  Eigen::Vector3d to_eye = (c.eye - Eigen::Vector3d(0, 0, 5)).normalized();
  EXPECT_NEAR(to_eye.x(), 0, 1e-9);                      // azimuth 90: on +y
  EXPECT_NEAR(to_eye.y(), std::cos(M_PI / 6), 1e-9);
  EXPECT_NEAR(to_eye.z(), std::sin(M_PI / 6), 1e-9);     // 30 degrees up
  EXPECT_NEAR((c.eye - Eigen::Vector3d(0, 0, 5)).norm(), 20 + std::sqrt(50.0), 1e-6);  // d beyond the bounding sphere
  EXPECT_NEAR(c.forward.dot(-to_eye), 1, 1e-12);
}

TEST(Config, BadValuesNameTheFileAndTheKey) {
  auto dir = std::filesystem::temp_directory_path() / "perclod-config-test";
  std::filesystem::create_directories(dir);
  auto write = [&](const char* name, const char* text) {
    auto p = (dir / name).string();
    std::ofstream(p) << text;
    return p;
  };
  auto expect_error = [](auto fn, const std::string& path, const std::string& what) {
    try {
      fn(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect_error(load_display_profile, write("neg.yaml", "dpi: -3\n"), "'dpi' must be a positive number");
  expect_error(load_display_profile, write("type.yaml", "width: wide\n"), "'width'");
  expect_error(load_display_profile, write("list.yaml", "- 1\n- 2\n"), "mapping");
  expect_error(load_batch_config, write("nomodel.yaml", "distances: [56]\n"), "'model' is required");
  expect_error(load_batch_config, write("nodist.yaml", "model: a.obj\n"), "'distances' is required");
  expect_error(load_batch_config, write("up.yaml", "model: a.obj\nup: x\ndistances: [5]\n"), "up axis");
  std::filesystem::remove_all(dir);
}
