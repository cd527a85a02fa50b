// A LOD judged against the original from recorded views: the LOD's render
// of each view perceived beside the original's, and the worst figures
// against the limits.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <deque>
#include <functional>
#include <future>
#include <iomanip>
#include <iterator>
#include <mutex>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <tuple>


#include "perclod/judge.h"

#include "perclod/worker.h"

namespace perclod {
using namespace detail;

JudgeSettings judge_settings_of(const LabelJob& job) { return {perception_for(job), job.overlap, building_lanes(job)}; }

std::vector<ViewRecord> record_views(Renderer& renderer, const Scene& scene, const std::vector<ViewTile>& tiles,
                                     const std::string& set) {
  renderer.set_scene(scene);
  std::vector<ViewRecord> records;
  std::vector<uint8_t> background;
  RenderOutput img;  // one set of buffers for every view
  for (const ViewTile& tile : tiles) {
    renderer.render(tile.camera, img);
    background_of(img, background);
    records.push_back(view_record(tile.name, tile.camera, img.rgb, background, set));
  }
  return records;
}

std::vector<ViewRecord> record_views(Renderer& renderer, const Scene& scene, const std::vector<std::string>& views,
                                     const Framing& framing, const std::string& set) {
  const Bounds bounds = scene_bounds(scene);
  std::vector<ViewTile> tiles;
  for (const auto& view : views)
    for (ViewTile& tile : frame_view(bounds, framing.up, view, framing.distance, framing.display))
      tiles.push_back(std::move(tile));
  return record_views(renderer, scene, tiles, set);
}

std::vector<ViewTile> framed_windows(const Bounds& box, const std::vector<std::string>& views, const Framing& framing,
                                     const PerceptionSettings& ps) {
  std::vector<ViewTile> tiles;
  for (const auto& view : views)
    for (ViewTile& tile : frame_view(box, framing.up, view, framing.distance, framing.display)) {
      tile.camera = perception_window(tile.camera, box, ps, true);
      tiles.push_back(std::move(tile));
    }
  return tiles;
}


namespace {

// One picture of a judged view: the original's luminance | the LOD's | the
// LOD's with perceptibly changed pixels red and pixels drawn by only one of
// the two blue. Each panel is the region either render draws (8 px margin),
// shrunk by a whole factor (box filter; a block is red or blue if any pixel
// in it is) to at most 400 px, or enlarged by one (nearest) to about 240 px,
// so a building far away is as readable as one close by.
Rgb8Image side_by_side(const ViewRecord& v, const std::vector<float>& original_luminance,
                       const std::vector<float>& lod_luminance, const std::vector<uint8_t>& lod_background,
                       const std::vector<uint8_t>& changed, int w, int h) {
  int x0 = w, y0 = h, x1 = -1, y1 = -1;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      if (v.background_at(x, y) && lod_background[i]) continue;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  if (x1 < 0) x0 = 0, y0 = 0, x1 = w - 1, y1 = h - 1;  // nothing drawn: the whole view
  constexpr int kMargin = 8;
  x0 = std::max(0, x0 - kMargin), y0 = std::max(0, y0 - kMargin);
  x1 = std::min(w - 1, x1 + kMargin), y1 = std::min(h - 1, y1 + kMargin);
  const int cw = x1 - x0 + 1, ch = y1 - y0 + 1, side = std::max(cw, ch);
  const int shrink = std::max(1, (side + 399) / 400), grow = shrink > 1 ? 1 : std::clamp(240 / side, 1, 8);
  const int pw = std::max(1, cw * grow / shrink), ph = std::max(1, ch * grow / shrink);
  constexpr int kGap = 4;
  Rgb8Image img;
  img.width = 3 * pw + 2 * kGap, img.height = ph;
  img.pixels.assign(size_t(img.width) * size_t(ph) * 3, 255);
  for (int y = 0; y < ph; ++y)
    for (int x = 0; x < pw; ++x) {
      // Source block of this output pixel.
      const int sx0 = x0 + x * shrink / grow, sy0 = y0 + y * shrink / grow;
      const int sx1 = std::min(x1 + 1, sx0 + std::max(1, shrink)), sy1 = std::min(y1 + 1, sy0 + std::max(1, shrink));
      double a = 0, b = 0;
      bool red = false, blue = false;
      int n = 0;
      for (int yy = sy0; yy < sy1; ++yy)
        for (int xx = sx0; xx < sx1; ++xx, ++n) {
          const size_t i = size_t(yy) * size_t(w) + size_t(xx);
          a += original_luminance[i], b += lod_luminance[i];
          red |= changed[i] != 0;
          blue |= (lod_background[i] != 0) != v.background_at(xx, yy);
        }
      n = std::max(n, 1);
      const auto put = [&](int panel, double l, uint8_t r, uint8_t g, uint8_t bl) {
        uint8_t* p = &img.pixels[(size_t(y) * size_t(img.width) + size_t(panel * (pw + kGap) + x)) * 3];
        const double k = l / n / 255.0;
        p[0] = uint8_t(std::lround(r * k)), p[1] = uint8_t(std::lround(g * k)), p[2] = uint8_t(std::lround(bl * k));
      };
      put(0, a, 255, 255, 255);
      put(1, b, 255, 255, 255);
      if (blue) put(2, std::max(b, 96.0 * n), 64, 96, 255);
      else if (red) put(2, std::max(b, 96.0 * n), 255, 48, 48);
      else put(2, b, 255, 255, 255);
    }
  for (int y = 0; y < ph; ++y)  // grey gaps between the panels
    for (int g = 0; g < kGap; ++g)
      for (int panel : {1, 2}) {
        uint8_t* p = &img.pixels[(size_t(y) * size_t(img.width) + size_t(panel * (pw + kGap) - kGap + g)) * 3];
        p[0] = p[1] = p[2] = 160;
      }
  return img;
}

// A judged view's floors from its record, and its visible figures over them.
void set_floors(ViewFigures& f, const ViewRecord& v) {
  f.visible_floor = v.visible_floor;
  f.visible_ratio = v.visible_floor < 0 ? 0.0 : f.visible_difference / std::max(v.visible_floor, kMinVisibleFloor);
  f.visible_floor_local = v.visible_floor_local;
  f.visible_local_ratio =
      v.visible_floor_local < 0 ? 0.0 : f.visible_local / std::max(v.visible_floor_local, kMinVisibleFloor);
}

// One judged view's figures from the LOD's render of it (and its picture).
struct ViewComparer {
  PerceptionSettings ps;
  PerceptionResult pr, original;
  std::vector<uint8_t> background, drawn_mask, changed_mask, original_rgb;
  SsimScratch ssim_scratch;

  ViewFigures operator()(const ViewRecord& v, RenderOutput& img, Rgb8Image* picture) {
    // The original's render rebuilt from its record and perceived as it was
    // when recorded (same pixels, same settings: the same floats).
    v.render_into(original_rgb);
    perceive_into(original_rgb.data(), v.camera.width, v.camera.height, ps, nullptr, original);
    return against(v, original, img, picture);
  }

  // The figures of the LOD's render (img) against the original's, perceived
  // without a mask (its luminance is rounded here).
  ViewFigures against(const ViewRecord& v, PerceptionResult& original, RenderOutput& img, Rgb8Image* picture) {
    const size_t kept = size_t(v.w) * size_t(v.h);
    if (img.width != v.camera.width || img.height != v.camera.height || v.background.size() != kept)
      throw std::logic_error("compare_lod_views: view size changed between recording and comparison");
    background_of(img, background);
    perceive_into(img.rgb.data(), img.width, img.height, ps, background.data(), pr);
    const size_t n = background.size();
    size_t drawn = 0, changed = 0, coverage_changed = 0, covered_original = 0;
    drawn_mask.assign(n, 0);
    changed_mask.assign(picture ? n : 0, 0);
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const size_t i = size_t(y) * size_t(img.width) + size_t(x);
        const long k = v.kept(x, y);
        const bool original_background = k < 0 || v.background[size_t(k)];
        covered_original += !original_background;
        if (background[i] && original_background) continue;
        drawn_mask[i] = 1;
        ++drawn;
        // Beyond the kept rectangle the original drew nothing within
        // kRecordMargin pixels: a LOD drawing there changes what is seen.
        const bool c = k < 0 || std::abs(pr.simulated[i] - original.simulated[i]) > ps.threshold;
        changed += c;
        if (picture) changed_mask[i] = c;
        coverage_changed += (background[i] != 0) != original_background;
      }
    // Both luminances on the same 8-bit grid, so an unchanged LOD scores 1.
    for (auto* lum : {&original.luminance, &pr.luminance})
      for (float& l : *lum) l = std::round(std::clamp(l, 0.f, 255.f));
    const double visible = visible_difference(pr.simulated.data(), original.simulated.data(), n,
                                              drawn_mask.data(), ps.threshold);
    const double ssim = ssim_mean(original.luminance.data(), pr.luminance.data(), img.width, img.height,
                                  drawn_mask.data(), &ssim_scratch);
    if (picture)
      *picture = side_by_side(v, original.luminance, pr.luminance, background, changed_mask, img.width, img.height);
    ViewFigures f;
    f.view = v.view;
    f.set = v.set;
    f.drawn_pixels = drawn;
    f.changed_pixels = changed;
    f.changed_fraction = drawn ? double(changed) / double(drawn) : 0.0;
    f.ssim_covered = ssim;
    f.covered_pixels_original = covered_original;
    f.coverage_changed_pixels = coverage_changed;
    f.silhouette_mismatch = covered_original ? double(coverage_changed) / double(covered_original)
                                             : (coverage_changed ? 1.0 : 0.0);
    f.visible_difference = visible;
    f.visible_local = visible_difference_local(pr.simulated.data(), original.simulated.data(), img.width, img.height,
                                               drawn_mask.data(), ps.threshold, kLocalBlockPx);
    set_floors(f, v);
    return f;
  }
};

// Item k of `count` rendered on this thread (which owns the OpenGL
// context) into one of n + 1 buffers while n workers (how.workers with
// how.overlap, else none) work on the items before it: item k on worker
// k % n with that worker's copy of `scratch`. Without workers each item is
// rendered, then worked on, here. work(scratch, k, render) must leave only
// item k's results.
template <class Scratch, class Render, class Work>
void render_then_work(size_t count, const JudgeSettings& how, const Scratch& scratch, Render render, Work work) {
  const size_t workers = how.overlap ? std::max<size_t>(1, how.workers) : 0;
  std::vector<Scratch> own(std::max<size_t>(1, workers), scratch);
  std::vector<RenderOutput> img(workers + 1);
  std::deque<std::future<void>> pending;  // items k - workers .. k - 1, whose buffers are not k's
  // After the buffers: an exception ends the workers (finishing what they
  // hold) before the buffers they work on are freed.
  std::vector<std::unique_ptr<Worker>> pool;
  for (size_t w = 0; w < workers; ++w) pool.push_back(std::make_unique<Worker>());
  for (size_t k = 0; k < count; ++k) {
    RenderOutput& out = img[k % (workers + 1)];
    render(k, out);
    if (!workers) {
      work(own[0], k, out);
      continue;
    }
    if (pending.size() == workers) {
      pending.front().get();
      pending.pop_front();
    }
    Scratch& s = own[k % workers];
    pending.push_back(pool[k % workers]->submit([&work, &s, &out, k] { work(s, k, out); }));
  }
  for (auto& p : pending) p.get();
}

}  // namespace

// The LOD's renders overlap the comparisons of the views before them, on
// how.workers threads; the figures are those of one view after another.
std::vector<ViewFigures> compare_lod_views(Renderer& renderer, const Scene& lod,
                                           const std::vector<ViewRecord>& original, const JudgeSettings& how,
                                           std::vector<Rgb8Image>* pictures) {
  renderer.set_scene(lod);
  std::vector<ViewFigures> views(original.size());
  std::vector<Rgb8Image> shots(pictures ? original.size() : 0);
  render_then_work(
      original.size(), how, ViewComparer{how.perception, {}, {}, {}, {}, {}, {}, {}},
      [&](size_t k, RenderOutput& img) { renderer.render(original[k].camera, img); },
      [&](ViewComparer& compare, size_t k, RenderOutput& img) {
        views[k] = compare(original[k], img, pictures ? &shots[k] : nullptr);
      });
  if (pictures)
    for (auto& p : shots) pictures->push_back(std::move(p));
  return views;
}

namespace {

// What measuring one view's floor needs besides the shifted render.
struct FloorScratch {
  std::vector<uint8_t> rgb, background, region;
  PerceptionResult shifted, unshifted;
};

// The camera of a view's floor: moved by kFloorShiftPx along the diagonal.
Camera floor_camera(Camera c) {
  c.shift_x += kFloorShiftPx / std::sqrt(2.0), c.shift_y += kFloorShiftPx / std::sqrt(2.0);
  return c;
}

// View v's floors from its original render moved by kFloorShiftPx (img)
// and the original's render as recorded, perceived without a mask.
void measure_floor(ViewRecord& v, const RenderOutput& img, const PerceptionResult& unshifted,
                   const PerceptionSettings& ps, FloorScratch& s) {
  background_of(img, s.background);
  perceive_into(img.rgb.data(), img.width, img.height, ps, nullptr, s.shifted);
  s.region.assign(s.background.size(), 0);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const size_t i = size_t(y) * size_t(img.width) + size_t(x);
      s.region[i] = !s.background[i] || !v.background_at(x, y);
    }
  v.visible_floor_local = visible_difference_local(s.shifted.simulated.data(), unshifted.simulated.data(), img.width,
                                                   img.height, s.region.data(), ps.threshold, kLocalBlockPx);
  v.visible_floor = visible_difference(s.shifted.simulated.data(), unshifted.simulated.data(), s.region.size(),
                                       s.region.data(), ps.threshold);
}

// A view whose quarter-pixel move crosses no pixel centre with an edge (one
// flat wall: every pixel of an edge's column flips together, or none does)
// has a floor near 0, and any LOD moving one edge there would look
// thousands of times over it. No view's floor is below kFloorOfMedian times
// the median of the views'.
void clamp_floors_to_median(std::vector<ViewRecord>& records) {
  auto clamp = [&](double ViewRecord::*floor) {
    std::vector<double> floors;
    for (const ViewRecord& v : records) floors.push_back(v.*floor);
    if (floors.empty()) return;
    std::nth_element(floors.begin(), floors.begin() + long(floors.size() / 2), floors.end());
    const double lowest = kFloorOfMedian * floors[floors.size() / 2];
    for (ViewRecord& v : records) v.*floor = std::max(v.*floor, lowest);
  };
  clamp(&ViewRecord::visible_floor);
  clamp(&ViewRecord::visible_floor_local);
}

}  // namespace

void measure_floors(Renderer& renderer, const Scene& original, std::vector<ViewRecord>& records,
                    const JudgeSettings& how) {
  renderer.set_scene(original);
  render_then_work(
      records.size(), how, FloorScratch{},
      [&](size_t k, RenderOutput& img) { renderer.render(floor_camera(records[k].camera), img); },
      [&](FloorScratch& scratch, size_t k, RenderOutput& img) {
        const ViewRecord& v = records[k];
        v.render_into(scratch.rgb);
        perceive_into(scratch.rgb.data(), img.width, img.height, how.perception, nullptr, scratch.unshifted);
        measure_floor(records[k], img, scratch.unshifted, how.perception, scratch);
      });
  clamp_floors_to_median(records);
}

Judgement judge_views(const std::vector<ViewFigures>& views, const FidelityLimits& limits) {
  Judgement j;
  j.limits = limits;
  WorstFigures& w = j.worst;
  for (const ViewFigures& v : views) {
    w.changed_fraction = std::max(w.changed_fraction, v.changed_fraction);
    w.silhouette_mismatch = std::max(w.silhouette_mismatch, v.silhouette_mismatch);
    w.ssim_covered = std::min(w.ssim_covered, v.ssim_covered);
    w.visible_ratio = std::max(w.visible_ratio, v.visible_ratio);
    w.visible_local_ratio = std::max(w.visible_local_ratio, v.visible_local_ratio);
    auto flag = [&](const char* measure, double value, double limit, bool over_limit) {
      if (over_limit) j.over_limits.push_back({v.view, v.set, measure, value, limit});
    };
    flag("changed_fraction", v.changed_fraction, limits.max_changed, v.changed_fraction > limits.max_changed);
    flag("ssim_covered", v.ssim_covered, limits.min_ssim, v.ssim_covered < limits.min_ssim);
    flag("silhouette_mismatch", v.silhouette_mismatch, limits.max_silhouette,
         v.silhouette_mismatch > limits.max_silhouette);
    flag("visible_ratio", v.visible_ratio, limits.max_visible, limits.max_visible > 0 && v.visible_ratio > limits.max_visible);
    flag("visible_local_ratio", v.visible_local_ratio, limits.max_visible_local,
         limits.max_visible_local > 0 && v.visible_local_ratio > limits.max_visible_local);
  }
  return j;
}

namespace {

// Whether triangles `a` of scene sa and `b` of sb draw the same: the same
// corners (bit for bit), components, colours and order. The renderer shades
// by face normal, so nothing else reaches the pixels.
bool same_triangles(const Scene& sa, const std::vector<uint32_t>& a, const Scene& sb, const std::vector<uint32_t>& b) {
  if (a.size() != b.size() || sa.offset != sb.offset) return false;
  for (size_t k = 0; k < a.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      const float* pa = &sa.positions[3 * size_t(sa.indices[3 * size_t(a[k]) + size_t(c)])];
      const float* pb = &sb.positions[3 * size_t(sb.indices[3 * size_t(b[k]) + size_t(c)])];
      if (std::memcmp(pa, pb, 3 * sizeof(float)) != 0) return false;
    }
    if (sa.component_of(a[k]) != sb.component_of(b[k])) return false;  // uncoloured: its component's colour
    const Material *ma = sa.material_of(a[k]), *mb = sb.material_of(b[k]);
    if ((ma == nullptr) != (mb == nullptr)) return false;
    if (ma && (ma->color != mb->color || ma->has_color != mb->has_color)) return false;
  }
  return true;
}

// `tiles` of `original` judged against `lod` as record_views,
// measure_floors and compare_lod_views judge them (the same figures), one
// view at a time: the original's render is perceived once, for its floor
// and its comparison, and no view's pixels are kept after it. `floors`
// holds each tile's floors as measured (before the clamp): when it holds
// one pair per tile they are taken, else they are measured into it.
std::vector<ViewFigures> judge_tiles(Renderer& renderer, const Scene& original, const Scene& lod,
                                     const std::vector<ViewTile>& tiles, const PerceptionSettings& ps,
                                     std::vector<std::pair<double, double>>& floors) {
  const bool known = floors.size() == tiles.size();
  if (!known) floors.clear();
  std::vector<ViewRecord> records;
  std::vector<ViewFigures> figures;
  RenderOutput img;  // one set of buffers for every render
  std::vector<uint8_t> background;
  PerceptionResult perceived;  // the original's render
  FloorScratch floor;
  ViewComparer compare{ps, {}, {}, {}, {}, {}, {}, {}};
  for (const ViewTile& tile : tiles) {
    renderer.set_scene(original);
    renderer.render(tile.camera, img);
    background_of(img, background);
    // The record's rectangle and mask only: the render is perceived now.
    records.push_back(view_record(tile.name, tile.camera, img.rgb, background, "held_out", false));
    ViewRecord& v = records.back();
    perceive_into(img.rgb.data(), img.width, img.height, ps, nullptr, perceived);
    if (known) {
      std::tie(v.visible_floor, v.visible_floor_local) = floors[records.size() - 1];
    } else {
      renderer.render(floor_camera(tile.camera), img);
      measure_floor(v, img, perceived, ps, floor);
      floors.emplace_back(v.visible_floor, v.visible_floor_local);
    }
    renderer.set_scene(lod);
    renderer.render(tile.camera, img);
    // The LOD's perception takes the shifted one's buffers: two perceptions
    // of a view held at once, not three (a large building's tiles are
    // whole frames, two lanes at a time).
    compare.pr = std::move(floor.shifted);
    figures.push_back(compare.against(v, perceived, img, nullptr));
    floor.shifted = std::move(compare.pr);
  }
  // The floors clamped over all the views, as measure_floors clamps them.
  clamp_floors_to_median(records);
  for (size_t k = 0; k < figures.size(); ++k) set_floors(figures[k], records[k]);
  return figures;
}

}  // namespace

std::vector<BuildingJudged> judge_buildings_alone(
    const Scene& original, const Scene& lod, const std::vector<std::string>& views, const Framing& framing,
    const JudgeSettings& how, size_t lanes, const std::function<void(size_t, size_t, const BuildingJudged&)>& done,
    const std::vector<uint8_t>* only, BuildingFloors* floors) {
  if (lod.component_names != original.component_names)
    throw std::invalid_argument("judge_buildings_alone: the LOD's components are not the original's");
  const Buildings buildings = find_buildings(original);
  const size_t nb = buildings.names.size();
  std::vector<std::vector<uint32_t>> tris(nb), lod_tris(nb);
  for (size_t t = 0; t < original.triangle_count(); ++t)
    tris[buildings.of_component[original.component_of(t)]].push_back(uint32_t(t));
  for (size_t t = 0; t < lod.triangle_count(); ++t)
    lod_tris[buildings.of_component[lod.component_of(t)]].push_back(uint32_t(t));
  std::vector<size_t> to_judge;  // buildings with triangles, in building order
  if (only && only->size() != nb) throw std::invalid_argument("judge_buildings_alone: a flag per building");
  if (floors) floors->resize(nb);  // each lane writes only its buildings' entries
  for (size_t b = 0; b < nb; ++b)
    if (!tris[b].empty() && (!only || (*only)[b])) to_judge.push_back(b);

  std::vector<BuildingJudged> out(to_judge.size());
  // The lanes are the parallelism: each judges its building view by view.
  lanes = std::clamp<size_t>(lanes, 1, std::max<size_t>(1, to_judge.size()));
  std::atomic<size_t> next{0};
  std::mutex lock;  // `done`, the count, the first error
  size_t finished = 0;
  std::exception_ptr error;
  auto run_lane = [&] {
    try {
      Renderer renderer;  // this thread's OpenGL context
      std::vector<uint32_t> vertex, lod_vertex;
      for (size_t k; (k = next++) < to_judge.size();) {
        const size_t b = to_judge[k];
        BuildingJudged& r = out[k];
        r.index = b;
        r.building = buildings.names[b];
        r.triangles = tris[b].size();
        r.lod_triangles = lod_tris[b].size();
        r.unchanged = same_triangles(original, tris[b], lod, lod_tris[b]);
        if (!r.unchanged) {
          const Scene alone = subset_scene(original, tris[b], vertex);
          const Scene lod_alone = subset_scene(lod, lod_tris[b], lod_vertex);
          std::vector<std::pair<double, double>> own;  // without a cache, this building's for this call
          r.views = judge_tiles(renderer, alone, lod_alone,
                                framed_windows(scene_bounds(alone), views, framing, how.perception), how.perception,
                                floors ? (*floors)[b] : own);
          for (ViewFigures& f : r.views) {
            f.building = r.building;
            f.view = r.building + "/" + f.view;
          }
        }
        std::lock_guard<std::mutex> g(lock);
        if (done) done(finished, to_judge.size(), r);
        ++finished;
      }
    } catch (...) {
      next = to_judge.size();  // the other lanes stop after their building
      std::lock_guard<std::mutex> g(lock);
      if (!error) error = std::current_exception();
    }
  };
  std::vector<std::thread> threads;
  try {
    for (size_t l = 1; l < lanes; ++l) threads.emplace_back(run_lane);
  } catch (...) {  // a thread could not start: the started ones stop after their building
    next = to_judge.size();
    for (std::thread& t : threads) t.join();
    throw;
  }
  run_lane();
  for (std::thread& t : threads) t.join();
  if (error) std::rethrow_exception(error);
  return out;
}

}  // namespace perclod
