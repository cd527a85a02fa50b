// bench_simplify: time and peak memory of perclod's labelled simplification
// beside meshoptimizer and OpenMesh's stock Decimater reaching the same
// triangle count, on a ~1M-triangle generated facade and on the 53 Ingolstadt
// LOD3 buildings. One process, same run; every measurement runs in a forked
// child so its peak RSS (getrusage of the child) is its own. Prints medians
// and ratios.
//
// Labels: from the real pipeline (perclod::label_scene): the four facade
// views at 56 m on the paper's display profile, octree tracer, default
// perception settings; both models are Z up. p(d) is the pixel footprint of
// that profile at 56 m.
//
// Rows:
//   perclod paper       label-constrained collapses until nothing is removable (the count N)
//   perclod bounded     same, error bounded by 1 x p(d)
//   perclod fidelity    the default mode: each label bounds its collapses (0.5 / 0.5 px;
//                       undisplayable triangles deleted or kept as keep_undisplayable: auto decides)
//   fidelity 1 thread   the same on one thread (chunks of pieces run on every core otherwise)
//   decimater+locks     the alternative design: OpenMesh Decimater with perceptible
//                       vertices locked, ModQuadric + ModAspectRatio + ModNormalFlipping
//   perclod qem         plain quadric to N, labels ignored
//   meshoptimizer       meshopt_simplify to N (welding by meshopt_generateVertexRemap included)
//   meshopt @bounded    the same, to perclod bounded's count
//   meshopt @fidelity   the same, to perclod fidelity's count
//   decimater stock     ModQuadric + ModAspectRatio(10) to N faces
//
// Then fidelity (2 threads, 1 thread) and meshopt @fidelity again, one run
// of each per round: their medians and the median of the per-round ratios,
// the figure to quote (a VM whose speed drifts over minutes skews medians
// of runs taken back to back).
//
// CPU s: user + system seconds of the median run's child, every thread.
//
// Also: a flat 80,000-triangle wall (the stock Decimater's zero-cost trap,
// docs/method.md section 5), ours in paper and bounded mode, meshoptimizer and the stock
// Decimater (ModQuadric + ModAspectRatio) at bounded's count.
//
// Usage: bench_simplify [--runs R] [--facade-triangles N] [--skip-decimater] [--no-city] [--csv FILE]
//                       [--labels default] [--distance D] [--step E[,U|,deleted]]
//   --step: the fidelity rows at a step of tighten_to_limits instead of the
//   asked bounds (fidelity_bounds: e_I = e_P = E px, undisplayable triangles
//   kept within U px (default E), or as keep_undisplayable: auto decides):
//   what `perclod run` writes where it ended at that step (the
//   million-triangle facade at 56 m: 0.25,4).
//   --labels default: labels from the default views and samples (kDefaultViews, samples: auto)
//   at D metres (default 56) instead of the four facades with one sample.
//   --csv FILE: one row per model and method (median seconds, triangles, peak MB).
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModAspectRatioT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <sys/resource.h>
#include <tbb/global_control.h>

#include <new>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#ifdef PERCLOD_HAVE_MESHOPTIMIZER
#include <meshoptimizer.h>
#endif

#include "decimater.h"
#include "perclod/display.h"
#include "perclod/facade.h"
#include "perclod/load.h"
#include "perclod/fidelity_search.h"
#include "perclod/label.h"
#include "perclod/undisplayable.h"
#include "perclod/simplify.h"

using namespace perclod;

namespace {

// ---- measurement -------------------------------------------------------

struct Sample {
  double seconds = 0;
  double cpu_seconds = 0;  // user + system, all threads of the child
  size_t triangles = 0;
  long peak_kb = 0;
  bool ok = false;
};

// A forked child inherits oneTBB's state but not its worker threads, and
// then runs every parallel loop on one thread. Waiting for the workers to
// finish first (the next parallel loop starts new ones, in the child too)
// lets the child use every core, as `perclod run` does. Returns false when
// oneTBB could not let its workers go.
bool release_tbb_workers() {
  tbb::task_scheduler_handle handle{tbb::attach{}};
  return tbb::finalize(handle, std::nothrow);
}

// Runs `work` (returns the output triangle count) in a forked child.
Sample run_forked(const std::function<size_t()>& work) {
  if (!release_tbb_workers()) std::fprintf(stderr, "  (oneTBB kept its workers: the child runs on one thread)\n");
  int fd[2];
  if (pipe(fd) != 0) return {};
  pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    auto t0 = std::chrono::steady_clock::now();
    size_t n = work();
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    double msg[2] = {s, double(n)};
    ssize_t w = write(fd[1], msg, sizeof msg);
    _exit(w == sizeof msg ? 0 : 1);
  }
  close(fd[1]);
  double msg[2] = {0, 0};
  ssize_t got = read(fd[0], msg, sizeof msg);
  close(fd[0]);
  int status = 0;
  rusage ru{};
  wait4(pid, &status, 0, &ru);
  Sample r;
  r.ok = got == sizeof msg && WIFEXITED(status) && WEXITSTATUS(status) == 0;
  r.seconds = msg[0];
  r.triangles = size_t(msg[1]);
  r.peak_kb = ru.ru_maxrss;
  // The child's CPU time includes its exit (a few ms of unmapping).
  r.cpu_seconds = double(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) + 1e-6 * double(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
  return r;
}

struct Row {
  std::string name;
  double seconds = 0;
  double cpu_seconds = 0;  // of the median run
  size_t triangles = 0;
  long peak_kb = 0;
};

// A method's row from its runs: the median run's seconds, CPU seconds and
// triangles, and the largest peak.
Row row_of(const std::string& name, std::vector<Sample> s) {
  Row r{name};
  if (s.empty()) return r;
  std::sort(s.begin(), s.end(), [](const Sample& a, const Sample& b) { return a.seconds < b.seconds; });
  const Sample& m = s[s.size() / 2];
  r.seconds = m.seconds;
  r.cpu_seconds = m.cpu_seconds;
  r.triangles = m.triangles;
  for (const Sample& x : s) r.peak_kb = std::max(r.peak_kb, x.peak_kb);
  return r;
}

Row measure(const std::string& name, int runs, const std::function<size_t()>& work) {
  std::vector<Sample> s;
  for (int i = 0; i < runs; ++i) {
    Sample x = run_forked(work);
    if (!x.ok) {
      std::fprintf(stderr, "  %s: run failed\n", name.c_str());
      continue;
    }
    s.push_back(x);
  }
  if (s.empty()) return Row{name};
  Row r = row_of(name, std::move(s));
  std::fprintf(stderr, "  %-18s %9.3f s  %9zu tris  %7.0f MB\n", name.c_str(), r.seconds, r.triangles,
               r.peak_kb / 1024.0);
  return r;
}

// Methods run in turn, one run of each per round, so a slow spell of the
// machine falls on all of them alike; the ratio of two methods is the
// median of their per-round ratios. (measure() runs one method's runs back
// to back: on a VM whose speed drifts by 2x over minutes its medians can
// favour whichever method ran in the fast spell.)
struct Interleaved {
  std::vector<Row> rows;
  std::vector<std::vector<double>> seconds;  // per method, per round
  // Median over rounds of seconds[a] / seconds[b].
  double ratio(size_t a, size_t b) const {
    std::vector<double> r;
    for (size_t i = 0; i < seconds[a].size() && i < seconds[b].size(); ++i)
      if (seconds[b][i] > 0) r.push_back(seconds[a][i] / seconds[b][i]);
    if (r.empty()) return 0;
    std::sort(r.begin(), r.end());
    return r.size() % 2 ? r[r.size() / 2] : 0.5 * (r[r.size() / 2 - 1] + r[r.size() / 2]);
  }
};

Interleaved measure_interleaved(const std::vector<std::string>& names,
                                const std::vector<std::function<size_t()>>& works, int runs) {
  Interleaved out;
  std::vector<std::vector<Sample>> samples(works.size());
  out.seconds.assign(works.size(), {});
  for (int round = 0; round < runs; ++round) {
    std::vector<Sample> got(works.size());
    bool ok = true;
    for (size_t k = 0; k < works.size(); ++k) ok &= (got[k] = run_forked(works[k])).ok;
    if (!ok) {  // a round counts only whole, so that its ratios pair up
      std::fprintf(stderr, "  interleaved round %d: a run failed\n", round);
      continue;
    }
    for (size_t k = 0; k < works.size(); ++k) {
      samples[k].push_back(got[k]);
      out.seconds[k].push_back(got[k].seconds);
    }
  }
  for (size_t k = 0; k < works.size(); ++k) out.rows.push_back(row_of(names[k], samples[k]));
  return out;
}

// ---- labels --------------------------------------------------------------

double pixel_footprint(double distance) { return display_pixel_footprint(DisplayProfile{}, distance); }

// --labels default: the default views and samples at --distance instead of
// the four facades with one sample at 56 m.
bool g_default_labels = false;
double g_distance = 56.0;
FidelitySearchStep g_step{-1, true};  // --step: e < 0 = the asked bounds

// The pipeline's labels of `scene` (four facades, one sample, or the
// defaults) at `distance`, Z up; and their undisplayable_exposure (what
// keep_undisplayable: auto decides from).
std::vector<Label> pipeline_labels(const Scene& scene, double distance, double& exposure) {
  auto t0 = std::chrono::steady_clock::now();
  Renderer renderer;
  OctreeTracer tracer(scene);
  LabelJob job;
  job.up = UpAxis::Z;
  job.views = parse_views(g_default_labels ? kDefaultViews : "facades", UpAxis::Z);
  if (g_default_labels) {
    job.samples = kDefaultSamples;
    job.combine = parse_combine_views(kDefaultCombineViews);
    job.perception = perception_settings_for(job.display);
  }
  job.distance = distance;
  std::vector<Label> labels = label_scene(renderer, scene, tracer, job).labels;
  std::fprintf(stderr, "  labelled in %.2f s (render, perceive, trace %zu views)\n",
               std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), job.views.size());
  exposure = undisplayable_exposure(scene, tracer, labels, framing_of(job));
  return labels;
}

// ---- peers -----------------------------------------------------------------

struct Welded {
  std::vector<float> positions;
  std::vector<unsigned> indices;
};

#ifdef PERCLOD_HAVE_MESHOPTIMIZER
Welded meshopt_weld(const Scene& s) {
  Welded w;
  std::vector<unsigned> remap(s.vertex_count());
  size_t n = meshopt_generateVertexRemap(remap.data(), s.indices.data(), s.indices.size(), s.positions.data(),
                                         s.vertex_count(), 3 * sizeof(float));
  w.indices.resize(s.indices.size());
  meshopt_remapIndexBuffer(w.indices.data(), s.indices.data(), s.indices.size(), remap.data());
  w.positions.resize(3 * n);
  meshopt_remapVertexBuffer(w.positions.data(), s.positions.data(), s.vertex_count(), 3 * sizeof(float),
                            remap.data());
  return w;
}

size_t meshopt_to(const Scene& s, size_t target) {
  Welded w = meshopt_weld(s);
  std::vector<unsigned> out(w.indices.size());
  size_t n = meshopt_simplify(out.data(), w.indices.data(), w.indices.size(), w.positions.data(),
                              w.positions.size() / 3, 3 * sizeof(float), 3 * target, 1.0f, 0, nullptr);
  return n / 3;
}
#endif

using bench::DMesh;

// A TriMesh from the scene, vertices welded exactly; refused (non-manifold)
// faces are re-added with their own vertices, like OpenMesh's reader does.
void build_dmesh(const Scene& s, DMesh& mesh, std::vector<uint32_t>& face_src) {
  omerr().disable();
  Welded w;
#ifdef PERCLOD_HAVE_MESHOPTIMIZER
  w = meshopt_weld(s);
#else
  w.positions = s.positions;
  w.indices.assign(s.indices.begin(), s.indices.end());
#endif
  std::vector<DMesh::VertexHandle> vh(w.positions.size() / 3);
  for (size_t i = 0; i < vh.size(); ++i)
    vh[i] = mesh.add_vertex(DMesh::Point(w.positions[3 * i], w.positions[3 * i + 1], w.positions[3 * i + 2]));
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    unsigned a = w.indices[3 * t], b = w.indices[3 * t + 1], c = w.indices[3 * t + 2];
    if (a == b || b == c || a == c) continue;  // the stock tools cannot hold these
    auto f = mesh.add_face(vh[a], vh[b], vh[c]);
    if (!f.is_valid()) {
      DMesh::VertexHandle d[3];
      for (int k = 0; k < 3; ++k) d[k] = mesh.add_vertex(mesh.point(vh[w.indices[3 * t + k]]));
      f = mesh.add_face(d[0], d[1], d[2]);
    }
    face_src.resize(f.idx() + 1);
    face_src[f.idx()] = uint32_t(t);
  }
  mesh.update_face_normals();
}

size_t decimater_stock_to(const Scene& s, size_t target) {
  DMesh mesh;
  std::vector<uint32_t> src;
  build_dmesh(s, mesh, src);
  bench::decimate_stock(mesh, target);
  mesh.garbage_collection();
  return mesh.n_faces();
}

size_t decimater_locked(const Scene& s, const std::vector<Label>& labels) {
  DMesh mesh;
  std::vector<uint32_t> src;
  build_dmesh(s, mesh, src);
  for (auto f : mesh.faces())
    if (labels[src[f.idx()]] == Label::Perceptible)
      for (auto v : mesh.fv_range(f)) mesh.status(v).set_locked(true);
  OpenMesh::Decimater::DecimaterT<DMesh> dec(mesh);
  OpenMesh::Decimater::ModQuadricT<DMesh>::Handle hq;
  OpenMesh::Decimater::ModAspectRatioT<DMesh>::Handle ha;
  OpenMesh::Decimater::ModNormalFlippingT<DMesh>::Handle hn;
  dec.add(hq);
  dec.add(ha);
  dec.add(hn);
  dec.module(hq).unset_max_err();
  dec.module(ha).set_aspect_ratio(10.0f);
  dec.module(hn).set_max_normal_deviation(60.0);
  dec.initialize();
  dec.decimate();
  mesh.garbage_collection();
  return mesh.n_faces();
}

// ---- one model ---------------------------------------------------------------

FILE* g_csv = nullptr;

void csv_rows(const std::string& model, size_t input, const std::vector<Row>& rows) {
  if (!g_csv) return;
  for (const Row& r : rows)
    std::fprintf(g_csv, "%s,%zu,%s,%.5f,%zu,%.1f,%.5f\n", model.c_str(), input, r.name.c_str(), r.seconds, r.triangles,
                 r.peak_kb / 1024.0, r.cpu_seconds);
  std::fflush(g_csv);
}

void bench_model(const std::string& title, const Scene& scene, int runs, bool with_decimater) {
  const double p = pixel_footprint(g_distance);
  double exposure = 0;
  std::vector<Label> labels = pipeline_labels(scene, g_distance, exposure);
  size_t count[3] = {0, 0, 0};
  for (Label l : labels) count[size_t(l)]++;
  std::printf("\n== %s: %zu triangles (perceptible %zu, imperceptible %zu, undisplayable %zu), p(%g m) = %.4f m, %d runs\n",
              title.c_str(), scene.triangle_count(), count[0], count[1], count[2], g_distance, p, runs);

  SimplifyOptions paper;
  Row ours = measure("perclod paper", runs, [&] { return simplify(scene, labels, paper).triangle_count(); });
  SimplifyOptions bounded;
  bounded.mode = SimplifyMode::Bounded;
  bounded.pixel_footprint = p;
  Row ours_b = measure("perclod bounded", runs, [&] { return simplify(scene, labels, bounded).triangle_count(); });
  SimplifyOptions fidelity;  // the defaults: e_P = e_I = 0.5 px, keep_undisplayable: auto
  fidelity.mode = SimplifyMode::Fidelity;
  fidelity.pixel_footprint = p;
  fidelity = choose_undisplayable(fidelity, exposure);
  if (fidelity.delete_undisplayable)
    std::printf("undisplayable exposure %.3f%%: fidelity deletes them\n", 100 * exposure);
  else
    std::printf("undisplayable exposure %.3f%%: fidelity keeps them (collapsed within %g px)\n", 100 * exposure,
                fidelity.bound_undisplayable_px);
  if (g_step.e >= 0) {
    fidelity = fidelity_bounds(fidelity, g_step);
    if (fidelity.delete_undisplayable)
      std::printf("fidelity at a tighter step: e_I = e_P = %g px, undisplayable deleted\n", g_step.e);
    else
      std::printf("fidelity at a tighter step: e_I = e_P = %g px, undisplayable kept within %g px\n", g_step.e,
                  fidelity.bound_undisplayable_px);
  }
  const std::function<size_t()> run_fidelity = [&] { return simplify(scene, labels, fidelity).triangle_count(); };
  // meshoptimizer runs on one thread; perclod simplifies chunks of pieces
  // on every core (two here). The same on one thread, for a like-for-like figure.
  const std::function<size_t()> run_fidelity_1 = [&] {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    return simplify(scene, labels, fidelity).triangle_count();
  };
  Row ours_f = measure("perclod fidelity", runs, run_fidelity);
  Row ours_f1 = measure("fidelity 1 thread", runs, run_fidelity_1);
  const size_t target = ours.triangles;
  SimplifyOptions qem;
  qem.mode = SimplifyMode::Qem;
  qem.target_triangles = target;
  Row ours_q = measure("perclod qem", runs, [&] { return simplify(scene, labels, qem).triangle_count(); });
  std::vector<Row> rows = {ours, ours_b, ours_f, ours_f1, ours_q};
#ifdef PERCLOD_HAVE_MESHOPTIMIZER
  rows.push_back(measure("meshoptimizer", runs, [&] { return meshopt_to(scene, target); }));
  const size_t target_b = ours_b.triangles;
  rows.push_back(measure("meshopt @bounded", runs, [&] { return meshopt_to(scene, target_b); }));
  const size_t target_f = ours_f.triangles;
  rows.push_back(measure("meshopt @fidelity", runs, [&] { return meshopt_to(scene, target_f); }));
  // The comparison, fidelity against meshoptimizer at its count,
  // again with the three in turn: the ratio to quote.
  Interleaved paired = measure_interleaved(
      {"fidelity", "fidelity 1 thread", "meshopt @fidelity"},
      {run_fidelity, run_fidelity_1, [&] { return meshopt_to(scene, target_f); }},
      runs);
  char paired_line[320];
  std::snprintf(paired_line, sizeof paired_line,
                "interleaved, one run of each per round, %zu rounds: fidelity %.3f s, 1 thread %.3f s, "
                "meshopt @fidelity %.3f s -> %zu; median per-round ratio to meshopt %.2f, 1 thread %.2f\n",
                paired.seconds[0].size(), paired.rows[0].seconds, paired.rows[1].seconds, paired.rows[2].seconds,
                paired.rows[2].triangles, paired.ratio(0, 2), paired.ratio(1, 2));
#else
  const char* paired_line = "";
#endif
  if (with_decimater) {
    rows.push_back(measure("decimater+locks", std::min(runs, 3), [&] { return decimater_locked(scene, labels); }));
    rows.push_back(measure("decimater stock", std::min(runs, 3), [&] { return decimater_stock_to(scene, target); }));
  }
  std::printf("%-18s %10s %8s %10s %10s %9s %14s\n", "method", "median s", "CPU s", "triangles", "peak MB", "x paper",
              "tris/s in");
  for (const Row& r : rows)
    std::printf("%-18s %10.3f %8.3f %10zu %10.0f %9.2f %14.0f\n", r.name.c_str(), r.seconds, r.cpu_seconds, r.triangles,
                r.peak_kb / 1024.0, ours.seconds > 0 ? r.seconds / ours.seconds : 0.0,
                r.seconds > 0 ? scene.triangle_count() / r.seconds : 0.0);
  csv_rows(title, scene.triangle_count(), rows);
  std::printf("target N = %zu (perclod paper's output); ratio column = method time / perclod paper time\n"
              "(meshoptimizer and the Decimater may stop short of their target: see the triangles column)\n",
              target);
  std::fputs(paired_line, stdout);
}

// The Decimater trap of docs/method.md section 5: a flat 200x200-quad wall (80,000 triangles, all
// zero-cost collapses), imperceptible but for one perceptible corner triangle.
void bench_flat_wall(int runs, bool with_decimater) {
  Scene s;
  const int n = 200;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) s.positions.insert(s.positions.end(), {0.1f * i, 0.0f, 0.1f * j});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      s.indices.insert(s.indices.end(), {a, c, b, a, d, c});  // facing -y
      s.component.insert(s.component.end(), {0, 0});
      s.material.insert(s.material.end(), {0, 0});
    }
  s.component_names = {"wall"};
  s.materials = {Material{"wall"}};
  std::vector<Label> labels(s.triangle_count(), Label::Imperceptible);
  labels[0] = Label::Perceptible;
  std::printf("\n== flat wall: %zu triangles, one perceptible, %d runs\n", s.triangle_count(), runs);
  SimplifyOptions paper;
  Row ours = measure("perclod paper", runs, [&] { return simplify(s, labels, paper).triangle_count(); });
  SimplifyOptions bounded;
  bounded.mode = SimplifyMode::Bounded;
  bounded.pixel_footprint = pixel_footprint(56.0);
  Row ours_b = measure("perclod bounded", runs, [&] { return simplify(s, labels, bounded).triangle_count(); });
  std::vector<Row> rows = {ours, ours_b};
#ifdef PERCLOD_HAVE_MESHOPTIMIZER
  rows.push_back(measure("meshopt @bounded", runs, [&] { return meshopt_to(s, ours_b.triangles); }));
#endif
  if (with_decimater)
    rows.push_back(measure("decimater stock", 1, [&] { return decimater_stock_to(s, ours_b.triangles); }));
  for (const Row& r : rows)
    std::printf("%-18s %10.3f s %10zu triangles %8.0f MB\n", r.name.c_str(), r.seconds, r.triangles, r.peak_kb / 1024.0);
  csv_rows("flat wall", s.triangle_count(), rows);
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 5;
  size_t facade_triangles = 1000000;
  bool with_decimater = true, with_city = true;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
    else if (a == "--no-city") with_city = false;
    else if (a == "--csv" && i + 1 < argc) {
      g_csv = std::fopen(argv[++i], "w");
      if (!g_csv) {
        std::perror(argv[i]);
        return 1;
      }
      std::fprintf(g_csv, "model,input_triangles,method,seconds,triangles,peak_mb,cpu_seconds\n");
    }
    else if (a == "--facade-triangles" && i + 1 < argc) facade_triangles = std::strtoull(argv[++i], nullptr, 10);
    else if (a == "--skip-decimater") with_decimater = false;
    else if (a == "--labels" && i + 1 < argc && std::string(argv[i + 1]) == "default") g_default_labels = true, ++i;
    else if (a == "--distance" && i + 1 < argc) g_distance = std::atof(argv[++i]);
    else if (a == "--step" && i + 1 < argc) {
      const std::string v = argv[++i];
      g_step.e = std::atof(v.c_str());
      const size_t comma = v.find(',');
      const std::string u = comma == std::string::npos ? "" : v.substr(comma + 1);
      g_step.keep_undisplayable = u != "deleted";
      if (!u.empty() && u != "deleted") g_step.e_undisplayable = std::atof(u.c_str());
    } else {
      std::fprintf(stderr, "usage: bench_simplify [--runs R] [--facade-triangles N] [--skip-decimater] [--no-city] "
                           "[--csv FILE] [--labels default] [--distance D] [--step E[,U|,deleted]]\n");
      return 2;
    }
  }
  std::printf("bench_simplify: medians of %d runs (Decimater rows: at most 3), each in a forked child;\n"
              "peak MB = largest child peak RSS (includes the input scene the child inherits)\n", runs);
  Row base = measure("(empty child)", 1, [] { return size_t(0); });
  std::printf("empty child peak RSS: %.0f MB\n", base.peak_kb / 1024.0);
  bench_flat_wall(runs, with_decimater);

  Scene facade = generate_facade(facade_params_for_triangles(facade_triangles));
  bench_model("generated facade", facade, runs, with_decimater);
  facade = Scene{};

  if (with_city) {
    std::string path = std::string(PERCLOD_SHARED_DATA) + "/ingolstadt/ingolstadt_lod3_all53.obj";
    Scene city = load_scene(path);
    bench_model("ingolstadt_lod3_all53.obj", city, runs, with_decimater);
  }
  if (g_csv) std::fclose(g_csv);
  return 0;
}
