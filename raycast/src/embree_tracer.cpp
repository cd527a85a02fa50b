// embree_tracer.cpp - Embree 3 as the reference and as a fast packet tracer.
//
// One triangle geometry with the scene's own index order (primID = triangle
// index), RTC_SCENE_FLAG_ROBUST (watertight along shared edges), medium build
// quality. Rays are exactly the octree's (pixel_rays.h): origin the float eye,
// direction the float pixel direction, [tnear, tfar] = [znear, zfar].
//
// Verify mode traces packets as Fast does, then applies the tie rule with a
// second, single-ray query per hit pixel: the ray restricted to the tie
// window around its nearest t (tie_window.h) with a context filter that
// records the smallest primID it sees and rejects every hit, so Embree
// reports them all (left to itself, Embree gives a hit at equal t to
// whichever triangle its traversal meets last).
#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "geometry_checks.h"
#include "perclod/raycast.h"
#include "pixel_rays.h"
#include "tie_window.h"

namespace perclod {

struct EmbreeTracer::Impl {
  EmbreeMode mode = EmbreeMode::Verify;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  size_t triangles = 0, vertices = 0;
  double build_seconds = 0;
  std::atomic<int64_t> device_bytes{0};  // what Embree reports allocating (BVH + buffers)

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

[[noreturn]] void embree_fail(RTCDevice device, const char* what) {
  const RTCError e = device ? rtcGetDeviceError(device) : RTC_ERROR_UNKNOWN;
  throw std::runtime_error(std::string("embree: ") + what + " failed (error " + std::to_string(int(e)) + ")");
}

// Embree's memory monitor: a running total of the device's allocations.
bool track_memory(void* user, ssize_t bytes, bool /*post*/) {
  static_cast<std::atomic<int64_t>*>(user)->fetch_add(int64_t(bytes), std::memory_order_relaxed);
  return true;
}

// Context of the tie query: the filter keeps the lowest primID.
struct TieContext {
  RTCIntersectContext context;
  unsigned int lowest;
};

void keep_lowest(const RTCFilterFunctionNArguments* args) {
  auto* ctx = reinterpret_cast<TieContext*>(args->context);
  for (unsigned int i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const unsigned int prim = RTCHitN_primID(args->hit, args->N, i);
    if (prim < ctx->lowest) ctx->lowest = prim;
    args->valid[i] = 0;  // reject: keep Embree looking for the others
  }
}

void set_ray(RTCRayHit& rh, const float o[3], const float d[3], float tnear, float tfar) {
  rh.ray.org_x = o[0];
  rh.ray.org_y = o[1];
  rh.ray.org_z = o[2];
  rh.ray.dir_x = d[0];
  rh.ray.dir_y = d[1];
  rh.ray.dir_z = d[2];
  rh.ray.tnear = tnear;
  rh.ray.tfar = tfar;
  rh.ray.time = 0;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

}  // namespace

EmbreeTracer::EmbreeTracer(const Scene& scene, EmbreeMode mode) : impl_(std::make_unique<Impl>()) {
  validate(scene);
  impl_->mode = mode;
  const auto t0 = std::chrono::steady_clock::now();
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) embree_fail(nullptr, "rtcNewDevice");
  rtcSetDeviceMemoryMonitorFunction(impl_->device, track_memory, &impl_->device_bytes);
  impl_->scene = rtcNewScene(impl_->device);
  if (!impl_->scene) embree_fail(impl_->device, "rtcNewScene");
  int flags = RTC_SCENE_FLAG_ROBUST;
  if (mode == EmbreeMode::Verify) flags |= RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION;
  rtcSetSceneFlags(impl_->scene, RTCSceneFlags(flags));
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_MEDIUM);
  impl_->triangles = scene.triangle_count();
  impl_->vertices = scene.vertex_count();
  if (impl_->triangles > 0) {
    RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!g) embree_fail(impl_->device, "rtcNewGeometry");
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), impl_->vertices));
    auto* ix = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(uint32_t), impl_->triangles));
    if (!v || !ix) {
      rtcReleaseGeometry(g);
      embree_fail(impl_->device, "rtcSetNewGeometryBuffer");
    }
    std::memcpy(v, scene.positions.data(), scene.positions.size() * sizeof(float));
    std::memcpy(ix, scene.indices.data(), scene.indices.size() * sizeof(uint32_t));
    rtcCommitGeometry(g);
    rtcAttachGeometry(impl_->scene, g);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(impl_->scene);
  if (rtcGetDeviceError(impl_->device) != RTC_ERROR_NONE) embree_fail(impl_->device, "rtcCommitScene");
  impl_->build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

EmbreeTracer::~EmbreeTracer() = default;

EmbreeMode EmbreeTracer::mode() const { return impl_->mode; }

const char* EmbreeTracer::name() const {
  switch (impl_->mode) {
    case EmbreeMode::Fast: return "embree-fast";
    case EmbreeMode::Single: return "embree-single";
    case EmbreeMode::Verify: return "embree-verify";
  }
  return "embree";
}

double EmbreeTracer::build_seconds() const { return impl_->build_seconds; }

size_t EmbreeTracer::memory_bytes() const {
  // Embree's own count of what the device holds (BVH, buffers, build
  // leftovers), from its memory monitor.
  const int64_t b = impl_->device_bytes.load(std::memory_order_relaxed);
  return b > 0 ? size_t(b) : 0;
}

void EmbreeTracer::trace(const Camera& cam, uint32_t* out, float* tout) const {
  detail::check_camera(cam);
  if (!out) throw std::invalid_argument("embree trace: output buffer is null");
  float eye[3];
  detail::eye_float(cam, eye);
  const float znear = float(cam.znear), zfar = float(cam.zfar);
  const int W = cam.width, H = cam.height;
  RTCScene sc = impl_->scene;
  const detail::PixelDirections dirs(cam);

  if (impl_->mode == EmbreeMode::Single) {  // one rtcIntersect1 per pixel (the benchmark's single-ray figure)
    tbb::parallel_for(tbb::blocked_range<int>(0, H, 4), [&](const tbb::blocked_range<int>& r) {
      detail::DenormalsOff ftz;
      RTCIntersectContext ctx;
      rtcInitIntersectContext(&ctx);
      ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
      for (int y = r.begin(); y < r.end(); ++y)
        for (int x = 0; x < W; ++x) {
          float d[3];
          dirs.direction(x, y, d);
          RTCRayHit rh;
          set_ray(rh, eye, d, znear, zfar);
          rtcIntersect1(sc, &ctx, &rh);
          const size_t o = size_t(y) * size_t(W) + size_t(x);
          const bool hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
          out[o] = hit ? rh.hit.primID + 1 : 0;
          if (tout) tout[o] = hit ? rh.ray.tfar : 0.0f;
        }
    });
    return;
  }

  // Rays in 4x4 packets (rtcIntersect16). Verify then applies the tie
  // rule to each hit with a second, single-ray query over the tie window
  // (the same hits as single rays give: the 1M facade's agreement figures
  // are the same to the pixel; 1.7x faster there).
  const bool verify = impl_->mode == EmbreeMode::Verify;
  const int tx = (W + 3) / 4, ty = (H + 3) / 4;
  tbb::parallel_for(tbb::blocked_range<int>(0, tx * ty, 16), [&](const tbb::blocked_range<int>& r) {
    detail::DenormalsOff ftz;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) RTCRayHit16 rh;
    alignas(64) int valid[16];
    float dir[16][3];
    for (int ti = r.begin(); ti < r.end(); ++ti) {
      const int x0 = (ti % tx) * 4, y0 = (ti / tx) * 4;
      for (int i = 0; i < 16; ++i) {
        const int x = x0 + (i & 3), y = y0 + (i >> 2);
        valid[i] = (x < W && y < H) ? -1 : 0;
        float* d = dir[i];
        d[0] = 0, d[1] = 0, d[2] = 1;
        if (valid[i]) dirs.direction(x, y, d);
        rh.ray.org_x[i] = eye[0];
        rh.ray.org_y[i] = eye[1];
        rh.ray.org_z[i] = eye[2];
        rh.ray.dir_x[i] = d[0];
        rh.ray.dir_y[i] = d[1];
        rh.ray.dir_z[i] = d[2];
        rh.ray.tnear[i] = znear;
        rh.ray.tfar[i] = zfar;
        rh.ray.time[i] = 0;
        rh.ray.mask[i] = 0xFFFFFFFFu;
        rh.ray.id[i] = unsigned(i);
        rh.ray.flags[i] = 0;
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.primID[i] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect16(valid, sc, &ctx, &rh);
      for (int i = 0; i < 16; ++i) {
        if (!valid[i]) continue;
        const size_t o = size_t(y0 + (i >> 2)) * size_t(W) + size_t(x0 + (i & 3));
        if (rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) {
          out[o] = 0;
          if (tout) tout[o] = 0.0f;
          continue;
        }
        const float t = rh.ray.tfar[i];
        unsigned int prim = rh.hit.primID[i];
        if (verify) {
          TieContext tc;
          rtcInitIntersectContext(&tc.context);
          tc.context.filter = keep_lowest;
          tc.lowest = std::numeric_limits<unsigned int>::max();
          RTCRayHit q;
          set_ray(q, eye, dir[i], detail::tie_window_start(t, znear), detail::tie_window_end(t, zfar));
          rtcIntersect1(sc, &tc.context, &q);
          if (tc.lowest < prim) prim = tc.lowest;
        }
        out[o] = prim + 1;
        if (tout) tout[o] = t;
      }
    }
  });
}

}  // namespace perclod
