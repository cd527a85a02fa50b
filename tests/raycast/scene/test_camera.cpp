// The camera: one definition for renderer and ray caster. Needs the scene
// types only (perclod_scene).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>

#include "perclod/camera.h"

using namespace perclod;

TEST(Camera, KnownPointsProjectToExpectedPixels) {
  // 90 degree vertical fov, 200x100: tan(45) = 1, so at depth 1 the image spans y in [-1, 1], x in [-2, 2].
  Camera c = look_at({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, M_PI / 2, 200, 100, 0.1, 100);
  double px, py, depth;
  ASSERT_TRUE(c.project({0, 0, -1}, px, py, depth));
  EXPECT_NEAR(px, 100.0, 1e-9);
  EXPECT_NEAR(py, 50.0, 1e-9);
  EXPECT_NEAR(depth, 1.0, 1e-12);
  ASSERT_TRUE(c.project({-2, 1, -1}, px, py, depth));  // top-left corner of the image
  EXPECT_NEAR(px, 0.0, 1e-9);
  EXPECT_NEAR(py, 0.0, 1e-9);
  ASSERT_TRUE(c.project({3, -1.5, -3}, px, py, depth));  // half of the half-extents, right and down
  EXPECT_NEAR(px, 100.0 + 100.0 * 0.5, 1e-9);
  EXPECT_NEAR(py, 50.0 + 50.0 * 0.5, 1e-9);
  EXPECT_NEAR(depth, 3.0, 1e-12);
  EXPECT_FALSE(c.project({0, 0, 1}, px, py, depth));  // behind the eye
}

TEST(Camera, RayThroughAProjectedPointHitsIt) {
  Camera c = look_at({3, 4, 5}, {0.5, -1, 0.2}, {0, 0, 1}, 0.6, 1280, 1024, 0.5, 500);
  Eigen::Vector3d p(1.25, -0.75, 0.5);
  double px, py, depth;
  ASSERT_TRUE(c.project(p, px, py, depth));
  Eigen::Vector3d d = c.ray_direction(px, py);
  EXPECT_NEAR(d.dot(c.forward), 1.0, 1e-12);  // un-normalised: unit along the view axis
  Eigen::Vector3d hit = c.eye + depth * d;     // t equals eye depth
  EXPECT_NEAR((hit - p).norm(), 0.0, 1e-9);
}

TEST(Camera, ProjectionMatrixAgreesWithProject) {
  Camera c = look_at({1, 2, 30}, {0, 0, 0}, {0, 1, 0}, 0.58, 640, 480, 2, 90);
  Eigen::Matrix4d m = c.projection() * c.view();
  for (Eigen::Vector3d p : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(3, -2, 5), Eigen::Vector3d(-4, 1, -20)}) {
    Eigen::Vector4d clip = m * p.homogeneous();
    Eigen::Vector3d ndc = clip.head<3>() / clip.w();
    double px, py, depth;
    ASSERT_TRUE(c.project(p, px, py, depth));
    EXPECT_NEAR((ndc.x() + 1) * 0.5 * c.width, px, 1e-9);
    EXPECT_NEAR((1 - ndc.y()) * 0.5 * c.height, py, 1e-9);  // GL's y is up, images' row 0 is the top
    // Reversed-Z: depth 1 at znear, 0 at zfar.
    EXPECT_NEAR(ndc.z(), c.znear * (c.zfar - depth) / (depth * (c.zfar - c.znear)), 1e-12);
  }
}
