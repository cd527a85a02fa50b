// Foundation figures: load time and peak memory of a real model and of a
// generated 1M-triangle facade, and warm render time per 1280x1024 view.
// Each case runs in its own child process so its peak RSS is its own.
//   bench_foundation [MODEL.obj ...]   (default: ingolstadt_lod3_all53.obj)
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "perclod/export.h"
#include "perclod/facade.h"
#include "perclod/load.h"
#include "perclod/render.h"
#include "perclod/views.h"

using namespace perclod;
using Clock = std::chrono::steady_clock;

static double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Loads, renders the four facades at 56 m: 1 cold + 5 warm frames each.
static void run_case(const std::string& what, UpAxis up) {
  auto t0 = Clock::now();
  Scene s = load_scene(what);
  double load_s = std::chrono::duration<double>(Clock::now() - t0).count();
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  double load_rss_mb = ru.ru_maxrss / 1024.0;
  Renderer r;
  r.set_scene(s);
  DisplayProfile d;
  std::vector<double> warm;
  double cold = 0;
  for (const auto& f : parse_facades("all", up)) {
    Camera c = facade_camera(scene_bounds(s), up, f, 56, d);
    RenderOptions opt;
    auto first = r.render(c, opt);
    if (cold == 0) cold = first.seconds;
    for (int i = 0; i < 5; ++i) warm.push_back(r.render(c, opt).seconds);
  }
  getrusage(RUSAGE_SELF, &ru);
  std::printf("%-50s tris %9zu  load %7.3f s  peak RSS after load %7.1f MB  render cold %6.1f ms  warm median %6.1f ms (n=%zu)  peak RSS with renderer %7.1f MB\n",
              what.c_str(), s.triangle_count(), load_s, load_rss_mb, cold * 1e3, median(warm) * 1e3, warm.size(),
              ru.ru_maxrss / 1024.0);
  std::fflush(stdout);
}

int main(int argc, char** argv) {
  std::vector<std::pair<std::string, UpAxis>> cases;
  for (int i = 1; i < argc; ++i) cases.emplace_back(argv[i], UpAxis::Z);
  if (cases.empty()) {
    cases.emplace_back(PERCLOD_SHARED_DATA "/ingolstadt/ingolstadt_lod3_all53.obj", UpAxis::Z);
    // The 1M-triangle facade is generated once and loaded from an OBJ file like a real model.
    std::string path = "/tmp/perclod_bench_facade_1m.obj";
    export_scene(generate_facade(facade_params_for_triangles(1000000)), path);
    cases.emplace_back(path, UpAxis::Z);
  }
  std::printf("bench_foundation: 1280x1024, facade views at 56 m, OSMesa llvmpipe (LP_NUM_THREADS=%s)\n",
              getenv("LP_NUM_THREADS") ? getenv("LP_NUM_THREADS") : "default");
  std::fflush(stdout);  // before fork, or the children print it again
  for (const auto& [what, up] : cases) {
    pid_t pid = fork();
    if (pid == 0) {
      run_case(what, up);
      _exit(0);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) std::printf("%s: failed\n", what.c_str());
  }
}
