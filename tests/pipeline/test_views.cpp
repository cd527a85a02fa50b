// Display profiles, facade and free views, and config errors. The camera
// itself (one definition for renderer and ray caster) is tested with the
// scene types, in raycast/scene/test_camera.cpp.
#include <gtest/gtest.h>
#include <unistd.h>

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

TEST(Views, PresetsExpandInOrderWithoutDuplicates) {
  EXPECT_EQ(parse_views("facades", UpAxis::Z), parse_facades("all", UpAxis::Z));
  EXPECT_EQ(parse_views("obliques", UpAxis::Y),
            (std::vector<std::string>{"az45el0", "az135el0", "az225el0", "az315el0"}));
  EXPECT_EQ(parse_views("top,+x,top", UpAxis::Z), (std::vector<std::string>{"top", "+x"}));
  EXPECT_EQ(parse_views("ring4el30", UpAxis::Z),
            (std::vector<std::string>{"az0el30", "az90el30", "az180el30", "az270el30"}));
  EXPECT_EQ(parse_views("ring2el0/45", UpAxis::Z),
            (std::vector<std::string>{"az0el0", "az180el0", "az0el45", "az180el45"}));
  EXPECT_EQ(parse_views("ring3", UpAxis::Z).size(), 9u);  // 3 azimuths x elevations 0, 30, 60
  EXPECT_EQ(parse_views(std::vector<std::string>{"facades", " top "}, UpAxis::Z).size(), 5u);
  EXPECT_EQ(parse_views(kDefaultViews, UpAxis::Z).size(), parse_views(kDefaultViews, UpAxis::Y).size());
  for (const char* bad : {"ring0", "ring8el", "ring8el90", "ring8elx", "ringx", "tops", "az10el90", "", "+y"}) {
    try {
      parse_views(bad, UpAxis::Y);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("view"), std::string::npos) << e.what();
    }
  }
}

TEST(Views, TopLooksDownFromAboveTheRoof) {
  Bounds b;
  b.lo = {-10, -4, 0};
  b.hi = {10, 4, 12};
  DisplayProfile d;
  Camera c = view_camera(b, UpAxis::Z, "top", 30, d);
  EXPECT_NEAR(c.eye.z(), 42, 1e-9);
  EXPECT_NEAR(c.forward.z(), -1, 1e-12);
  EXPECT_NEAR(c.up.y(), 1, 1e-12);  // north up in the image
  Camera y = view_camera(b, UpAxis::Y, "top", 30, d);
  EXPECT_NEAR(y.forward.y(), -1, 1e-12);
  EXPECT_NEAR(y.eye.y(), 4 + 30, 1e-9);
}

// Every box corner lies inside some tile; a view that fits stays one camera.
TEST(Views, FrameViewTilesAModelThatOverfillsTheFrame) {
  Bounds b;
  b.lo = {-20, -1, 0};
  b.hi = {20, 1, 15};
  DisplayProfile d;
  for (const char* view : {"-y", "az30el20", "top"}) {
    auto far = frame_view(b, UpAxis::Z, view, 200, d);
    ASSERT_EQ(far.size(), 1u) << view;
    EXPECT_EQ(far[0].name, view);
    auto near = frame_view(b, UpAxis::Z, view, 5, d);
    EXPECT_GT(near.size(), 4u) << view;
    EXPECT_EQ(near[1].name, std::string(view) + "_t1");
    // Sample the box densely: every point projects into some tile's image.
    for (int i = 0; i <= 20; ++i)
      for (int j = 0; j <= 10; ++j)
        for (int k = 0; k <= 10; ++k) {
          Eigen::Vector3d p(-20 + 2.0 * i, -1 + 0.2 * j, 1.5 * k);
          bool inside = false;
          for (const auto& t : near) {
            double px, py, depth;
            inside |= t.camera.project(p, px, py, depth) && px >= 0 && px <= t.camera.width && py >= 0 &&
                      py <= t.camera.height && depth >= t.camera.znear && depth <= t.camera.zfar;
          }
          EXPECT_TRUE(inside) << view << " misses " << p.transpose();
        }
    // Same direction as the untiled view, eyes panned.
    EXPECT_NEAR(near[0].camera.forward.dot(far[0].camera.forward), 1, 1e-12);
  }
  EXPECT_THROW(frame_view(b, UpAxis::Z, "-y", 0.01, d, 64), std::invalid_argument);
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

// Issue 12 A/C: the whole config is checked before any work, and mistakes
// yaml-cpp or the old loader accepted silently are errors naming the file.
TEST(Config, EveryMistakeIsAnErrorNamingTheFile) {
  auto dir = std::filesystem::temp_directory_path() / ("perclod-config-strict-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  auto write = [&](const std::string& name, const std::string& text) {
    auto p = (dir / name).string();
    std::ofstream(p) << text;
    return p;
  };
  write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string good_display = write("ok-display.yaml", "width: 64\nheight: 48\ndpi: 90\nviewer_distance_m: 0.5\n");
  auto expect_error = [](auto fn, const std::string& path, const std::string& what,
                         const std::string& names = "") {
    try {
      fn(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const std::exception& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind(names.empty() ? path : names, 0), 0u) << msg;  // starts with the file
      EXPECT_NE(msg.find(what), std::string::npos) << msg;
    }
  };
  const std::string base = "model: m.obj\ndistances: [56]\n";
  expect_error(load_batch_config, write("typo.yaml", base + "verfy: true\n"), "unknown key 'verfy' (did you mean 'verify'?)");
  expect_error(load_batch_config, write("typo2.yaml", base + "colour: red\n"),
               "known keys: cityjson_lod, combine_views, crs, crs_origin, debug_images, display");
  expect_error(load_batch_config, write("dup.yaml", base + "model: other.obj\n"), "'model' appears twice");
  expect_error(load_batch_config, write("qem.yaml", base + "simplify: qem\n"), "needs 'target'");
  expect_error(load_batch_config, write("target0.yaml", base + "simplify: qem\ntarget: 0\n"), "'target'");
  expect_error(load_batch_config, write("target-paper.yaml", base + "target: 100\n"), "only to 'simplify: qem'");
  expect_error(load_batch_config, write("abc.yaml", "model: m.obj\ndistances: [abc]\n"), "'distances'");
  expect_error(load_batch_config, write("facades.yaml", base + "facades: +q\n"), "'facades'");
  expect_error(load_batch_config, write("views.yaml", base + "views: [facades, ring0]\n"), "'views': view 'ring0'");
  expect_error(load_batch_config, write("views2.yaml", base + "views: {a: 1}\n"), "'views' must be");
  expect_error(load_batch_config, write("both.yaml", base + "views: top\nfacades: all\n"), "not both");
  expect_error(load_batch_config, write("spp.yaml", base + "samples: 3\n"), "'samples'");
  expect_error(load_batch_config, write("pb.yaml", base + "per_building: maybe\n"), "'per_building'");
  expect_error(load_batch_config, write("gs.yaml", base + "group_span: -1\n"), "'group_span'");
  expect_error(load_batch_config, write("gs.yaml", base + "group_span: .nan\n"), "'group_span'");
  expect_error(load_batch_config, write("cv.yaml", base + "combine_views: all\n"),
               "'combine_views': combine_views must be any or pooled, not 'all'");
  expect_error(load_batch_config, write("out.yaml", base + "out: \"\"\n"), "'out'");
  expect_error(load_batch_config, write("mode.yaml", base + "simplify: fidel\n"), "'simplify' must be fidelity");
  expect_error(load_batch_config, write("ep.yaml", base + "e_perceptible: -1\n"), "'e_perceptible' must be");
  expect_error(load_batch_config, write("ei.yaml", base + "simplify: paper\ne_imperceptible: 2\n"),
               "'e_imperceptible' applies only to 'simplify: fidelity'");
  expect_error(load_batch_config, write("eu.yaml", base + "e_undisplayable: -2\n"), "'e_undisplayable' must be");
  expect_error(load_batch_config, write("eu2.yaml", base + "simplify: paper\ne_undisplayable: 2\n"),
               "'e_undisplayable' applies only to 'simplify: fidelity'");
  expect_error(load_batch_config, write("eu3.yaml", base + "keep_undisplayable: false\ne_undisplayable: 2\n"),
               "'keep_undisplayable: false' deletes them");
  expect_error(load_batch_config, write("judge.yaml", base + "judge_views: az30\n"), "'judge_views': view 'az30'");
  expect_error(load_batch_config, write("maxc.yaml", base + "max_changed: 2\n"), "'max_changed' must be a fraction");
  expect_error(load_batch_config, write("maxs.yaml", base + "max_silhouette: -0.1\n"), "'max_silhouette'");
  expect_error(load_batch_config, write("strict.yaml", base + "strict: maybe\n"), "'strict'");
  expect_error(load_batch_config, write("mins.yaml", base + "min_ssim: 1.2\n"), "'min_ssim' must be within [0, 1]");
  expect_error(load_batch_config, write("ft4.yaml", base + "fidelity_target: {min_ssim: -1}\n"),
               "'fidelity_target': min_ssim");
  expect_error(load_batch_config, write("ft.yaml", base + "fidelity_target: 0.02\n"), "'fidelity_target' must be a mapping");
  expect_error(load_batch_config, write("ft2.yaml", base + "fidelity_target: {max_chnged: 0.02}\n"),
               "unknown key 'max_chnged'");
  expect_error(load_batch_config, write("ft3.yaml", base + "fidelity_target: {max_changed: 1.5}\n"),
               "'fidelity_target': max_changed");
  expect_error(load_batch_config, write("nomodel-file.yaml", "model: gone.obj\ndistances: [56]\n"), "no such file");
  const std::string missing_display = (dir / "gone.yaml").string();
  expect_error(load_batch_config, write("nodisplay.yaml", base + "display: gone.yaml\n"), "no such file",
               missing_display);
  const std::string bad_display = write("nodpi.yaml", "width: 64\nheight: 48\nviewer_distance_m: 0.5\n");
  expect_error(load_batch_config, write("baddisplay.yaml", base + "display: nodpi.yaml\n"), "'dpi' is required",
               bad_display);

  // Display profiles: every size key is required, unknown keys are refused.
  for (const char* key : {"width", "height", "dpi", "viewer_distance_m"}) {
    std::string text;
    for (const char* line : {"width: 64\n", "height: 48\n", "dpi: 90\n", "viewer_distance_m: 0.5\n"})
      if (std::string(line).rfind(key, 0) != 0) text += line;
    expect_error(load_display_profile, write(std::string("no-") + key + ".yaml", text),
                 std::string("'") + key + "' is required");
  }
  expect_error(load_display_profile, write("dpl.yaml", "width: 64\nheight: 48\ndpi: 90\nviewer_distance_m: 0.5\ndip: 3\n"),
               "unknown key 'dip'");

  // The default job: fidelity mode with its bounds, held-out judging, the limits.
  LodJob d = lod_job(load_batch_config(write("default.yaml", base + "display: ok-display.yaml\n")));
  EXPECT_EQ(d.simplify.mode, SimplifyMode::Fidelity);
  EXPECT_EQ(d.simplify.bound_perceptible_px, kDefaultBoundPerceptiblePx);
  EXPECT_EQ(d.simplify.bound_imperceptible_px, kDefaultBoundImperceptiblePx);
  EXPECT_TRUE(d.simplify.delete_undisplayable);
  EXPECT_EQ(d.judge_views, parse_views(kDefaultJudgeViews, UpAxis::Y));
  // The default limit is perceptual: the quarter-pixel floor; the raw figures are reported only.
  EXPECT_EQ(d.limits.max_visible, 1.0);
  EXPECT_EQ(d.limits.max_changed, 1.0);
  EXPECT_EQ(d.limits.max_silhouette, 1.0);
  EXPECT_FALSE(d.fidelity_target);
  LodJob t = lod_job(load_batch_config(write(
      "target.yaml", base + "display: ok-display.yaml\njudge_views: none\ne_imperceptible: 3\n"
                            "fidelity_target: {max_silhouette: 0.005}\n")));
  EXPECT_TRUE(t.judge_views.empty());
  EXPECT_EQ(t.simplify.bound_imperceptible_px, 3.0);
  EXPECT_TRUE(t.fidelity_target);
  EXPECT_EQ(t.target.max_silhouette, 0.005);
  EXPECT_EQ(t.target.max_changed, 1.0);  // from max_changed's default
  EXPECT_EQ(t.target.max_visible, 1.0);  // and max_visible's
  EXPECT_EQ(d.limits.min_ssim, 0.0);       // no SSIM limit unless asked
  EXPECT_EQ(t.target.min_ssim, 0.0);
  // e_undisplayable keeps the undisplayable triangles and bounds their collapses.
  LodJob u = lod_job(load_batch_config(write("eu-ok.yaml", base + "display: ok-display.yaml\ne_undisplayable: 4\n")));
  EXPECT_FALSE(u.simplify.delete_undisplayable);
  EXPECT_EQ(u.simplify.bound_undisplayable_px, 4.0);
  EXPECT_EQ(d.simplify.bound_undisplayable_px, INFINITY);
  // It joins the settings (and so the up-to-date hash) only when given.
  EXPECT_EQ(settings_json(load_batch_config(write("eu-ok2.yaml", base + "display: ok-display.yaml\ne_undisplayable: 4\n")))
                .value("e_undisplayable", -1.0),
            4.0);
  EXPECT_FALSE(settings_json(load_batch_config(write("eu-none.yaml", base + "display: ok-display.yaml\n")))
                   .contains("e_undisplayable"));
  LodJob s = lod_job(load_batch_config(write("ssim.yaml", base + "display: ok-display.yaml\nmin_ssim: 0.97\n"
                                                                 "fidelity_target: {min_ssim: 0.95}\n")));
  EXPECT_EQ(s.limits.min_ssim, 0.97);
  EXPECT_EQ(s.target.min_ssim, 0.95);
  EXPECT_EQ(s.target.max_changed, 1.0);

  // A correct qem config maps its target onto the job.
  BatchConfig c = load_batch_config(write("qem-ok.yaml", base + "simplify: qem\ntarget: 500\ndisplay: ok-display.yaml\n"));
  EXPECT_EQ(c.target, 500u);
  EXPECT_EQ(lod_job(c).simplify.target_triangles, 500u);
  EXPECT_EQ(lod_job(c).label.display.width, 64);
  std::filesystem::remove_all(dir);
}
