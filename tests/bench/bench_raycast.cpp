// bench_raycast - primary-ray throughput of the octree against Embree.
//
// Same scene, same rays (1280x1024 pixel centres of one facade view), same
// thread count (tbb::global_control at 1 and 2). Prints, per scene: build
// times and index memory, Mrays/s medians of several runs for the octree,
// Embree rtcIntersect1 (EmbreeMode::Single), rtcIntersect16 (Fast) and the
// verify mode, the OSMesa ID buffer (a render of the same view: IDs and
// colour, read back, as Mrays/s-equivalent pixels per second), the ratio
// octree / rtcIntersect16, labelling's 4 samples per pixel (the octree's
// trace_samples, one walk of its structure for all four, beside one octree
// trace and one rtcIntersect16 pass per sample), and the octree-vs-Embree
// agreement. Scenes:
// generated facades of the sizes asked for (default ~1M triangles) and
// ingolstadt_lod3_all53.obj (loaded with perclod/load.h).
//
//   bench_raycast [runs=5] [--quick] [--sizes 10000,100000,...] [--no-real] [--csv FILE]
//     --quick: 200k-triangle facade only; --csv: one row per scene, view,
//     thread count and tracer (BENCHMARKS.md's tracer chart reads it).
#include <tbb/global_control.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <stdexcept>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "bench_common.h"
#include "perclod/display.h"
#include "perclod/facade.h"
#include "perclod/load.h"
#include "perclod/raycast.h"
#include "perclod/render.h"
#include "perclod/views.h"

using namespace perclod;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

FILE* g_csv = nullptr;

// One CSV row: scene,triangles,view,threads,tracer,mrays,build_s,memory_mb.
void csv_row(const std::string& scene, size_t tris, const std::string& view, int threads, const char* tracer,
             double mrays, double build_s, double memory_mb) {
  if (!g_csv) return;
  std::fprintf(g_csv, "%s,%zu,%s,%d,%s,%.4f,%.4f,%.2f\n", scene.c_str(), tris, view.c_str(), threads, tracer, mrays,
               build_s, memory_mb);
  std::fflush(g_csv);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Median Mrays/s over `runs` traces (after one warm-up trace).
double mrays(const Tracer& tracer, const Camera& cam, int runs, std::vector<uint32_t>& out) {
  const size_t n = size_t(cam.width) * size_t(cam.height);
  out.resize(n);
  tracer.trace(cam, out.data());
  std::vector<double> rates;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    tracer.trace(cam, out.data());
    rates.push_back(double(n) / seconds_since(t0) * 1e-6);
  }
  return median(rates);
}

// Median Mrays/s of 4 samples per pixel (sample_offsets(4)) over `runs`
// calls, after a warm-up: `one_walk` calls the tracer's trace_samples (the
// octree's walks its structure once for all four), otherwise Tracer's
// default, one trace per shifted camera.
double mrays_samples(const Tracer& tracer, const Camera& cam, int runs, bool one_walk) {
  const size_t n = size_t(cam.width) * size_t(cam.height);
  const auto offsets = sample_offsets(4);
  std::vector<std::vector<uint32_t>> out(offsets.size(), std::vector<uint32_t>(n));
  std::vector<uint32_t*> ptr;
  for (auto& o : out) ptr.push_back(o.data());
  auto call = [&] {
    if (one_walk) tracer.trace_samples(cam, offsets, ptr.data());
    else tracer.Tracer::trace_samples(cam, offsets, ptr.data());
  };
  call();
  std::vector<double> rates;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    call();
    rates.push_back(double(n * offsets.size()) / seconds_since(t0) * 1e-6);
  }
  return median(rates);
}

// Median megapixels/s of OSMesa renders of `cam` (IDs and colour read back),
// after one warm-up render. The renderer runs on one thread whatever TBB is
// allowed: Mesa's llvmpipe threads are its own (LP_NUM_THREADS).
double id_buffer_mrays(Renderer& renderer, const Camera& cam, int runs) {
  const size_t n = size_t(cam.width) * size_t(cam.height);
  renderer.render(cam);
  std::vector<double> rates;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    RenderOutput out = renderer.render(cam);
    rates.push_back(double(n) / seconds_since(t0) * 1e-6);
  }
  return median(rates);
}

// The views: the -y facade (Z up) at the distance where the model fills the
// image width, and at a quarter of it (the closer marking-render view).
std::vector<std::pair<std::string, Camera>> bench_cameras(const Scene& s) {
  const Bounds b = scene_bounds(s);
  DisplayProfile display;  // the paper's 1280x1024 profile
  Camera probe = facade_camera(b, UpAxis::Z, "-y", 10.0, display);
  const double half_w = 0.5 * (b.hi[0] - b.lo[0]);
  const double tan_x = probe.tan_half_y() * probe.aspect();
  const double d = std::max(1.0, 0.95 * half_w / tan_x);
  return {{"-y facade, fills the width", facade_camera(b, UpAxis::Z, "-y", d, display)},
          {"-y facade, a quarter of that distance", facade_camera(b, UpAxis::Z, "-y", d / 4, display)}};
}

void bench_scene(const std::string& name, const Scene& scene, int runs, Renderer& renderer) {
  std::printf("\n== %s: %zu triangles, %zu components\n", name.c_str(), scene.triangle_count(),
              scene.component_count());

  // Builds (median of 3, default TBB threads).
  std::vector<double> ob, eb;
  for (int r = 0; r < 3; ++r) {
    ob.push_back(OctreeTracer(scene).build_seconds());
    eb.push_back(EmbreeTracer(scene, EmbreeMode::Fast).build_seconds());
  }
  const OctreeTracer octree(scene);
  const EmbreeTracer single(scene, EmbreeMode::Single), fast(scene, EmbreeMode::Fast),
      verify(scene, EmbreeMode::Verify);
  const auto st = octree.stats();
  const double tris = double(std::max<size_t>(1, scene.triangle_count()));
  std::printf("build (median of 3, all threads): octree %.3f s, embree (robust, medium) %.3f s\n", median(ob),
              median(eb));
  std::printf("octree index: %.1f MB = %.1f bytes/triangle (triangle copies 40 B/tri included); "
              "%zu octree nodes, %zu leaves, depth %d, %zu leaf refs, %zu components, %zu BVH nodes\n",
              octree.memory_bytes() / 1e6, octree.memory_bytes() / tris, st.octree_nodes, st.octree_leaves,
              st.depth_reached, st.leaf_references, st.components, st.bvh_nodes);
  std::printf("embree device memory (its monitor, robust BVH + buffers): %.1f MB = %.1f bytes/triangle\n",
              fast.memory_bytes() / 1e6, fast.memory_bytes() / tris);
  const auto r0 = std::chrono::steady_clock::now();
  renderer.set_scene(scene);
  const double upload = seconds_since(r0);

  const size_t nt = scene.triangle_count();
  for (const auto& [view, cam] : bench_cameras(scene)) {
    const std::string vkey = view.find("quarter") != std::string::npos ? "quarter" : "fills";
    std::printf("-- view: %s, %dx%d, eye %.1f m from the centre, znear %.3f zfar %.1f\n", view.c_str(), cam.width,
                cam.height, (scene_bounds(scene).center()[1] - cam.eye.y()), cam.znear, cam.zfar);
    std::vector<uint32_t> a, b;
    for (int threads : {1, 2}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
      const double o = mrays(octree, cam, runs, a);
      const double e1 = mrays(single, cam, runs, b);
      const double e16 = mrays(fast, cam, runs, b);
      const double ev = mrays(verify, cam, std::max(1, runs / 2), b);
      std::printf("threads %d: Mrays/s octree %6.2f | embree rtcIntersect1 %6.2f | rtcIntersect16 %6.2f | "
                  "verify %6.2f || octree/embree16 %.2f, octree/embree1 %.2f\n",
                  threads, o, e1, e16, ev, o / e16, o / e1);
      csv_row(name, nt, vkey, threads, "octree", o, median(ob), octree.memory_bytes() / 1e6);
      csv_row(name, nt, vkey, threads, "embree_intersect1", e1, median(eb), single.memory_bytes() / 1e6);
      csv_row(name, nt, vkey, threads, "embree_intersect16", e16, median(eb), fast.memory_bytes() / 1e6);
      csv_row(name, nt, vkey, threads, "embree_verify", ev, median(eb), verify.memory_bytes() / 1e6);
      // Labelling's default: 4 samples per pixel.
      const double o4 = mrays_samples(octree, cam, runs, true), o4x = mrays_samples(octree, cam, runs, false);
      const double e4 = mrays_samples(fast, cam, runs, false);
      std::printf("threads %d, 4 samples per pixel: Mrays/s octree one walk %6.2f | octree one trace per sample "
                  "%6.2f | rtcIntersect16 %6.2f || one walk / four traces %.2f, one walk / embree16 %.2f\n",
                  threads, o4, o4x, e4, o4 / o4x, o4 / e4);
      csv_row(name, nt, vkey, threads, "octree_4spp_one_walk", o4, median(ob), octree.memory_bytes() / 1e6);
      csv_row(name, nt, vkey, threads, "octree_4spp_four_traces", o4x, median(ob), octree.memory_bytes() / 1e6);
      csv_row(name, nt, vkey, threads, "embree_intersect16_4spp", e4, median(eb), fast.memory_bytes() / 1e6);
    }
    const double idb = id_buffer_mrays(renderer, cam, runs);
    std::printf("OSMesa ID buffer (render + read back, its own threads): %6.2f Mpixels/s, upload %.3f s\n", idb,
                upload);
    csv_row(name, nt, vkey, 0, "osmesa_id_buffer", idb, upload, 0.0);

    const size_t n = size_t(cam.width) * size_t(cam.height);
    a.assign(n, 0);
    b.assign(n, 0);
    octree.trace(cam, a.data());
    verify.trace(cam, b.data());
    Agreement g = compare_traced(scene, cam, a.data(), b.data());
    std::printf("octree vs embree verify: covered %llu of %llu px, identical %.5f%%, ties %llu, edge grazes %llu, "
                "real disagreements %llu\n",
                (unsigned long long)g.covered, (unsigned long long)g.pixels, 100.0 * g.identical_rate(),
                (unsigned long long)g.ties, (unsigned long long)g.edge_grazes,
                (unsigned long long)g.real_disagreements);
    fast.trace(cam, b.data());
    g = compare_traced(scene, cam, a.data(), b.data());
    std::printf("octree vs embree fast (no tie rule): identical %.5f%%, ties %llu, edge grazes %llu, real %llu\n",
                100.0 * g.identical_rate(), (unsigned long long)g.ties, (unsigned long long)g.edge_grazes,
                (unsigned long long)g.real_disagreements);
  }
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 5;
  bool real = true;
  std::vector<size_t> sizes = {1000000};
  std::string csv;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      sizes = {200000};
      real = false;
    } else if (a == "--no-real") {
      real = false;
    } else if (a == "--sizes" && i + 1 < argc) {
      sizes.clear();
      for (const auto& n : bench::split(argv[++i], ',')) sizes.push_back(std::strtoull(n.c_str(), nullptr, 10));
    } else if (a == "--csv" && i + 1 < argc) {
      csv = argv[++i];
    } else if (!a.empty() && std::isdigit(static_cast<unsigned char>(a[0]))) {
      runs = std::max(1, std::atoi(a.c_str()));
    } else {
      std::fprintf(stderr, "usage: bench_raycast [runs=5] [--quick] [--sizes N,N,...] [--no-real] [--csv FILE]\n");
      return 2;
    }
  }
  try {
    if (!csv.empty()) {
      g_csv = std::fopen(csv.c_str(), "w");
      if (!g_csv) throw std::runtime_error(csv + ": cannot write");
      std::fprintf(g_csv, "scene,triangles,view,threads,tracer,mrays,build_s,memory_mb\n");
    }
    Renderer renderer;
    for (size_t target : sizes) {
      const auto t0 = std::chrono::steady_clock::now();
      const Scene facade = generate_facade(facade_params_for_triangles(target));
      std::printf("generated facade in %.2f s\n", seconds_since(t0));
      bench_scene("facade_" + std::to_string(target), facade, runs, renderer);
    }
    if (real) {
      const std::string path = std::string(PERCLOD_SHARED_DATA) + "/ingolstadt/ingolstadt_lod3_all53.obj";
      const Scene city = load_scene(path);
      bench_scene("ingolstadt_lod3_all53", city, runs, renderer);
    }
    if (g_csv) std::fclose(g_csv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_raycast: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
