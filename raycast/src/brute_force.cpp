// brute_force.cpp - the test oracle: every pixel's ray against every triangle.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <stdexcept>

#include "geometry_checks.h"
#include "perclod/raycast.h"
#include "pixel_rays.h"
#include "tie_window.h"
#include "watertight.h"

namespace perclod {

BruteForceTracer::BruteForceTracer(const Scene& scene) {
  validate(scene);
  tris_.resize(9 * scene.triangle_count());
  for (size_t t = 0; t < scene.triangle_count(); ++t)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k)
        tris_[9 * t + 3 * c + k] = scene.positions[3 * size_t(scene.indices[3 * t + c]) + k];
}

void BruteForceTracer::trace(const Camera& cam, uint32_t* out, float* tout) const {
  detail::check_camera(cam);
  if (!out) throw std::invalid_argument("brute-force trace: output buffer is null");
  float eye[3];
  detail::eye_float(cam, eye);
  const float znear = float(cam.znear), zfar = float(cam.zfar);
  const size_t nt = tris_.size() / 9;
  const detail::PixelDirections dirs(cam);
  tbb::parallel_for(tbb::blocked_range<int>(0, cam.height), [&](const tbb::blocked_range<int>& r) {
    detail::DenormalsOff ftz;
    for (int y = r.begin(); y < r.end(); ++y)
      for (int x = 0; x < cam.width; ++x) {
        float d[3];
        dirs.direction(x, y, d);
        const detail::ShearedRay ray = detail::shear_ray(d);
        // Pass 1: the nearest t. Pass 2: lowest index within its tie window.
        float best = zfar;
        bool any = false;
        auto test = [&](size_t t, float tmax, float& th) {
          float A[3], B[3], C[3];
          for (int k = 0; k < 3; ++k) {
            A[k] = tris_[9 * t + k] - eye[k];
            B[k] = tris_[9 * t + 3 + k] - eye[k];
            C[k] = tris_[9 * t + 6 + k] - eye[k];
          }
          return detail::watertight_hit(ray, A, B, C, znear, tmax, th);
        };
        for (size_t t = 0; t < nt; ++t) {
          float th;
          if (test(t, best, th)) {
            best = th;
            any = true;
          }
        }
        const size_t o = size_t(y) * size_t(cam.width) + size_t(x);
        out[o] = 0;
        if (tout) tout[o] = 0.0f;
        if (!any) continue;
        const float bound = detail::tie_window_end(best, zfar);
        for (size_t t = 0; t < nt; ++t) {
          float th;
          if (test(t, bound, th)) {
            out[o] = uint32_t(t) + 1;
            break;
          }
        }
        if (tout) tout[o] = best;
      }
  });
}

}  // namespace perclod
