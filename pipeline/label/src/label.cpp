// Labelling (the method's sections 2-4 for one distance): per view (framed,
// tiled when needed) render -> perceive -> trace each sample -> count; labels
// from the counts, combined over views; per-building views; the labels file
// and marking renders.
#include <cstdio>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <future>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "perclod/image_io.h"
#include "perclod/labels_io.h"
#include "perclod/label.h"
#include "perclod/packing.h"
#include "perclod/worker.h"
#include "view_pass.h"

namespace perclod {
using namespace detail;
namespace {

// Marking colours of `labels`: each labelling view and tile coloured from its
// own ID buffer (no second render), and with job.marking_near each view
// (untiled: the whole model, cut off where it overfills the frame) rendered
// from distance * closer_factor.
std::vector<std::string> write_marking_images(Renderer& renderer, const Scene& scene,
                                              const std::vector<Label>& labels, std::vector<IdBuffer>& id_buffers,
                                              const LabelJob& job) {
  std::vector<std::string> files;
  if (job.out.dir.empty() || !job.write_view_images) return files;
  RenderOptions opt;
  opt.triangle_colors = marking_colors(labels);
  opt.want_ids = false;
  std::vector<uint32_t> ids;
  for (IdBuffer& b : id_buffers) {
    b.ids_into(ids);
    files.push_back(job.out.view(b.view, job.distance, "_marking.png"));
    write_png_via(job.images, files.back(), b.camera.width, b.camera.height, 3,
                  shade_ids(scene, b.camera, ids, opt.triangle_colors, opt));
    b.packed_ids = {};
  }
  if (!job.marking_near) return files;
  const Bounds bounds = scene_bounds(scene);
  for (const auto& view : job.views) {
    const Camera closer = view_camera(bounds, job.up, view, job.distance * job.closer_factor, job.display);
    RenderOutput o = renderer.render(closer, opt);
    files.push_back(job.out.view(view, job.distance, "_marking_near.png"));
    write_png_via(job.images, files.back(), o.width, o.height, 3, std::move(o.rgb));
  }
  return files;
}

}  // namespace

namespace {

// The job as labelled (auto's effective samples) after checking that its
// settings can be combined.
LabelJob checked_job(const LabelJob& asked) {
  LabelJob job = asked;
  job.samples = effective_samples(asked);
  if (job.views.empty()) throw std::invalid_argument("no views to label from");
  if (job.samples != kAutoSamples) sample_offsets(job.samples);  // checks the count
  const int grid = sample_grid(job.samples);  // 0 unless an ordered grid of samples
  // (auto with keep_unsampled_surface is 4 samples by now: effective_samples.)
  if ((job.mask_per_sample || grid) && job.keep_unsampled_surface && job.samples > 1)
    throw std::invalid_argument(
        "keep_unsampled_surface cannot be combined with mask_per_sample or a grid of samples (9, 16): the "
        "unsampled-surface rule needs every sample of a pixel in one picture");
  return job;
}

// Which building each triangle belongs to, and each building's box (empty
// for a building without triangles).
struct BuildingTriangles {
  std::vector<uint32_t> owner;
  std::vector<Bounds> box;
  std::vector<std::vector<uint32_t>> triangles;  // each building's, in model order
};
BuildingTriangles building_triangles(const Scene& scene, const Buildings& buildings) {
  BuildingTriangles bt;
  const size_t nt = scene.triangle_count();
  bt.owner.resize(nt);
  bt.box.assign(buildings.names.size(), Bounds::empty());
  bt.triangles.resize(buildings.names.size());
  for (size_t t = 0; t < nt; ++t) {
    bt.owner[t] = buildings.of_component[scene.component_of(t)];
    bt.triangles[bt.owner[t]].push_back(uint32_t(t));
    for (int k = 0; k < 3; ++k) bt.box[bt.owner[t]].grow(&scene.positions[3 * size_t(scene.indices[3 * t + k])]);
  }
  return bt;
}

// What per-building labelling frames its views on: buildings, or groups of
// them (LabelJob::group_span). owner: each triangle's unit; box: each unit's.
struct LabelUnits {
  std::vector<std::vector<uint32_t>> members;  // buildings of each unit
  std::vector<uint32_t> owner;
  std::vector<Bounds> box;
  std::vector<double> distance;  // what its views are framed at
};
// A building's views put its eye `distance` outside its bounding sphere; a
// group's put the group's centre where its median building's centre would
// be: its nearer buildings are seen closer, its farther ones further.
double group_frame_distance(const BuildingTriangles& bt, const std::vector<uint32_t>& members, const Bounds& box,
                            double distance) {
  if (members.size() == 1) return distance;
  std::vector<float> radius;
  for (uint32_t b : members) radius.push_back(0.5f * bt.box[b].diagonal());
  std::nth_element(radius.begin(), radius.begin() + radius.size() / 2, radius.end());
  return std::max(0.5 * distance, distance - (0.5 * box.diagonal() - radius[radius.size() / 2]));
}
LabelUnits label_units(const BuildingTriangles& bt, UpAxis up, double span, double distance) {
  LabelUnits u;
  u.members = group_boxes(bt.box, up, span * distance);
  std::vector<uint32_t> unit_of(bt.box.size(), 0);
  u.box.assign(u.members.size(), Bounds::empty());
  for (uint32_t g = 0; g < u.members.size(); ++g)
    for (uint32_t b : u.members[g]) {
      unit_of[b] = g;
      u.box[g].grow(bt.box[b].lo.data());
      u.box[g].grow(bt.box[b].hi.data());
    }
  for (uint32_t g = 0; g < u.members.size(); ++g)
    u.distance.push_back(group_frame_distance(bt, u.members[g], u.box[g], distance));
  u.owner.resize(bt.owner.size());
  for (size_t t = 0; t < bt.owner.size(); ++t) u.owner[t] = unit_of[bt.owner[t]];
  return u;
}

// A view framed on one building may put its eye inside a neighbour's box (a
// kiosk beside a hall): it sees that neighbour from inside, and the
// building's labels come from its other views. Counted per building (or
// group: the buildings outside it).
bool eye_inside_other(const Camera& cam, const std::vector<Bounds>& box, const std::vector<uint32_t>& own) {
  for (uint32_t k = 0; k < box.size(); ++k) {
    if (std::binary_search(own.begin(), own.end(), k) || box[k].is_empty()) continue;
    bool in = true;
    for (int a = 0; a < 3 && in; ++a) in = cam.eye[a] >= box[k].lo[a] && cam.eye[a] <= box[k].hi[a];
    if (in) return true;
  }
  return false;
}

// One building as a scene of its own (subset_scene): its triangles
// (`triangles` of the model, which `triangle` keeps) on its own vertices.
struct BuildingAlone {
  Scene scene;
  std::vector<uint32_t> triangle;
};
BuildingAlone building_alone(const Scene& scene, const std::vector<uint32_t>& triangles,
                             std::vector<uint32_t>& vertex) {
  return {subset_scene(scene, triangles, vertex), triangles};
}

// How well a group's view saw one of its buildings, over the pixels whose
// centre ray crosses the building's box: `own` drew the building, `hidden`
// drew something nearer than the near plane of the building's own view
// (box_near_depth), which that view leaves out: a member in
// front, the far side of a yard.
struct MemberSight {
  uint64_t own = 0, hidden = 0;
};
MemberSight member_sight(const Camera& cam, const RenderOutput& image, const Bounds& box,
                         const std::vector<uint32_t>& building_of, uint32_t building) {
  MemberSight s;
  const double near = box_near_depth(cam, box);
  const PixelRect r = box_rect(cam, box);  // wider than the rays that can cross the box
  for (int y = r.y; y < r.y + r.h; ++y)
    for (int x = r.x; x < r.x + r.w; ++x) {
      const size_t i = size_t(y) * image.width + x;
      const uint32_t id = image.ids[i];
      if (!id) continue;
      const Eigen::Vector3d d = cam.ray_direction(x + 0.5, y + 0.5);
      double t0 = 0, t1 = INFINITY;
      for (int a = 0; a < 3 && t0 <= t1; ++a) {
        const double ta = (box.lo[a] - cam.eye[a]) / d[a], tb = (box.hi[a] - cam.eye[a]) / d[a];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
      }
      if (!(t0 <= t1)) continue;  // the ray misses the box (NaN from a zero component too)
      if (building_of[id - 1] == building) ++s.own;
      else if (image.depth[i] > 0 && image.depth[i] < near) ++s.hidden;
    }
  return s;
}

// A group's member takes its own views in a direction where what its own
// views would leave out (MemberSight::hidden) covers more than this share
// of the pixels where the group's views saw it or that hid it. (On the
// Delft tile at 427 m in groups of 0.5: 53% of the members' directions
// are over 2%, 40% over 20%; at 0 a single pixel would do.)
constexpr double kHiddenShareLimit = 0.02;

// The views framed on one building or group: their passes (pipeline
// items), tile names, samplings chosen and eyes inside other buildings
// (counted only for views that draw them: not `alone`).
struct OwnViews {
  std::vector<ViewPass> passes;
  std::vector<std::string> names;
  std::map<std::string, size_t> chosen;
  size_t eyes_inside = 0;
  bool alone = false;  // the views being added show their building alone
  // The views being added draw and read only their window on the unit
  // (window_rect), where no sample can hit it outside; a group's read
  // their whole frame (member_sight looks there).
  bool window = false;
};
// What a group's views leave for settle_group: per tile its direction (an
// index into job.views) and how well it saw each member; per pass its
// counts of the group's triangles, in the order of `tris`.
struct GroupViews {
  std::vector<size_t> view_of;
  std::vector<std::vector<MemberSight>> sight;
  std::vector<uint32_t> tris;
  std::vector<TriangleCounts> kept;
};
// What labelling a building alone needs of its own: an OpenGL context and
// building_alone's vertex map (kept between buildings). Each thread that
// labels buildings alone has one.
struct AloneLane {
  std::unique_ptr<Renderer> renderer;
  std::vector<uint32_t> vertex;
};

// label_scene's work: the whole-model views, then each building's own, then
// the labels from what they counted.
class SceneLabeller {
 public:
  SceneLabeller(Renderer& renderer, const Scene& scene, const Tracer& tracer, const LabelJob& asked,
                LabelProgress* progress, const EmbreeTracer* verify_tracer)
      : renderer_(renderer), scene_(scene), tracer_(tracer), job_(checked_job(asked)), progress_(progress),
        nt_(scene.triangle_count()), bounds_(scene_bounds(scene)), ps_(perception_for(job_)),
        depth_(finds_unsampled_surface(job_)), automatic_(job_.samples == kAutoSamples),
        write_files_(!job_.out.dir.empty()), acc_(nt_) {
    // One Embree reference is built here unless the caller keeps one for the job.
    if (job_.verify && !verify_tracer) own_ = std::make_unique<EmbreeTracer>(scene, EmbreeMode::Verify);
    reference_ = job_.verify ? (verify_tracer ? verify_tracer : own_.get()) : nullptr;
  }

  LabelResult run() {
    const auto t0 = Clock::now();
    if (write_files_) ensure_directory(job_.out.dir);
    renderer_.set_scene(scene_);
    begin_report();
    const bool per_building = labels_per_building();
    res_.report.model_views_counted = !per_building || !each_building_alone() || job_.model_views_beside_alone;
    label_model_views();
    if (per_building) {
      const auto t_b = Clock::now();
      label_buildings();
      res_.report.seconds_buildings = since(t_b);
    }
    res_.report.seconds = since(t0);
    return finish();
  }

 private:
  void begin_report();
  void plan_model_views();
  void on_model_view_seen(const ViewPass& vp, ViewOutcome& o);
  void on_model_view_counted(const ViewPass& vp, ViewOutcome& o);
  void label_model_views();
  bool labels_per_building();
  bool each_building_alone() const { return job_.own_views_alone && job_.group_span == 0; }
  void label_buildings();
  void label_buildings_in_lanes(const LabelUnits& units, const BuildingTriangles& bt, size_t lanes);
  BuildingLabelling label_unit(uint32_t u, const LabelUnits& units, const BuildingTriangles& bt,
                               ViewPipeline& pipeline, OwnViews& own, AloneLane& lane);
  size_t add_framed_view(const Bounds& box, const std::vector<uint32_t>& own, const std::vector<Bounds>& boxes,
                         size_t v, double distance, size_t triangles, OwnViews& out);
  void count_alone(uint32_t building, const BuildingTriangles& bt, const OwnViews& own, size_t from,
                   ViewPipeline& pipeline, AloneLane& lane);
  void count_in_place(const std::vector<uint32_t>& owner, uint32_t unit, const Bounds& box, const OwnViews& own,
                      size_t from, ViewPipeline& pipeline);
  void count_group(uint32_t u, const LabelUnits& units, const BuildingTriangles& bt, ViewPipeline& pipeline,
                   const OwnViews& own, GroupViews& gv);
  void settle_group(uint32_t u, const LabelUnits& units, const BuildingTriangles& bt, const GroupViews& gv,
                    ViewPipeline& pipeline, OwnViews& own, BuildingLabelling& entry, AloneLane& lane);
  LabelResult finish();

  Renderer& renderer_;
  const Scene& scene_;
  const Tracer& tracer_;
  const LabelJob job_;
  LabelProgress* progress_;
  const size_t nt_;
  const Bounds bounds_;
  const PerceptionSettings ps_;
  const bool depth_;      // the renders' depth, for add_unsampled_surface
  const bool automatic_;  // samples auto: each view picks its sampling
  const bool write_files_;
  std::unique_ptr<EmbreeTracer> own_;
  AloneLane lane_;  // job.own_views_alone: for buildings labelled alone on this thread
  const EmbreeTracer* reference_ = nullptr;
  LabelResult res_;
  Accumulator acc_;
  std::vector<ViewTile> tiles_;
  // Pipeline item k renders passes_[k]; a view's first pass stands for it in
  // the records, images and report.
  std::vector<ViewPass> passes_;
  Buildings buildings_;
};

// The report's header: the distance, tracer and how views are sampled and combined.
void SceneLabeller::begin_report() {
  res_.totals.traced.assign(nt_, 0);
  res_.totals.imperceptible.assign(nt_, 0);
  const int grid = sample_grid(job_.samples);
  LabelReport& r = res_.report;
  r.distance = job_.distance;
  r.tracer = tracer_.name();
  r.samples = job_.samples;
  r.combine_views = job_.combine == CombineViews::Pooled ? "pooled" : "any";
  r.keep_unsampled_surface = depth_;
  r.mask_per_sample = job_.mask_per_sample || grid;
  r.sample_grid = grid;
  r.automatic = automatic_;
  r.view_images = write_files_ && job_.write_view_images;
}

// The whole model's views framed into tiles, each tile's sampling and passes.
void SceneLabeller::plan_model_views() {
  for (const auto& view : job_.views)
    for (ViewTile& tile : frame_view(bounds_, job_.up, view, job_.distance, job_.display))
      tiles_.push_back(std::move(tile));
  std::map<std::string, size_t> chosen;  // with samples auto: views per setting
  for (size_t i = 0; i < tiles_.size(); ++i) {
    const Camera window = perception_window(tiles_[i].camera, bounds_, ps_);
    const ViewSampling vs = sampling_of(job_, tiles_[i].camera, window, nt_, bounds_);
    if (automatic_) ++chosen[sampling_name(vs)];
    add_view_passes(i, tiles_[i].camera, window, vs, passes_);
  }
  if (automatic_) res_.report.sampling_chosen = chosen;
}

// A whole-model view rendered and perceived: record it (for judging, when
// it counts), queue its images.
void SceneLabeller::on_model_view_seen(const ViewPass& vp, ViewOutcome& o) {
  if (vp.pass) return;
  const ViewTile& tile = tiles_[vp.tile];
  if (res_.report.model_views_counted)
    res_.views.push_back(
        view_record(tile.name, kept_picture_camera(vp.camera, vp.grid()), o.image.rgb, o.background, "labelling"));
  if (!write_files_) return;
  auto file = [&](const char* suffix) { return job_.out.view(tile.name, job_.distance, suffix); };
  const int w = o.image.width, h = o.image.height;
  if (job_.write_view_images) write_png_via(job_.images, file(".png"), w, h, 3, std::move(o.image.rgb));
  if (job_.write_perception_images) {
    write_png_via(job_.images, file("_simulated.png"), w, h, 1, simulated_view(o.perception));
    write_png_via(job_.images, file("_difference.png"), w, h, 1, difference_view(o.perception));
    write_png_via(job_.images, file("_mask.png"), w, h, 1, mask_view(o.perception));
  }
}

// A whole-model view traced and counted: keep its IDs for the marking, report it.
void SceneLabeller::on_model_view_counted(const ViewPass& vp, ViewOutcome& o) {
  const ViewTile& tile = tiles_[vp.tile];
  for (const auto& [step, s] : o.report.seconds) res_.report.step_seconds[step] += s;
  if (vp.pass == 0) {
    if (write_files_ && job_.write_view_images)
      res_.id_buffers.push_back(IdBuffer{tile.name, kept_picture_camera(vp.camera, vp.grid()), std::move(o.packed_ids)});
    res_.report.views.push_back(o.report);
    if (automatic_) res_.report.views.back().sampling = sampling_name(vp.sampling);
  } else {
    add_pass_report(res_.report.views.back(), o.report, vp.passes);
  }
  if (progress_ && vp.pass + 1 == vp.passes) progress_->view_labelled(tile.name, job_.distance, res_.report.views.back());
}

// Every pass of every whole-model view, rendering overlapped with tracing.
// When they do not count (each building labelled from its own views alone)
// they are drawn only for what else they give: each view's render,
// perception and marking images, with job.verify its octree-Embree
// agreement, and its line in the report.
void SceneLabeller::label_model_views() {
  const bool counted = res_.report.model_views_counted;
  if (!counted && !(write_files_ && job_.write_view_images) && !job_.verify) return;
  plan_model_views();
  ViewPipeline pipeline(
      job_.overlap, [&](size_t k, ViewOutcome& o) { on_model_view_seen(passes_[k], o); },
      [&](size_t k, ViewOutcome& o) { on_model_view_counted(passes_[k], o); });
  for (const ViewPass& vp : passes_)
    pipeline.add([&](ViewOutcome& o) { see_view(renderer_, ps_, vp.camera, depth_, o, vp.grid()); },
                 [&](ViewOutcome& o) {
                   count_view(scene_, tracer_, reference_, job_, vp.sampling, tiles_[vp.tile].name, vp.camera,
                              nullptr, 0, nullptr, counted ? &res_ : nullptr, counted ? &acc_ : nullptr, o);
                   o.counts = {};
                   if (vp.pass == 0 && write_files_ && job_.write_view_images)  // packed here, on the worker
                     o.packed_ids = pack_bytes(o.image.ids.data(), o.image.ids.size() * sizeof(uint32_t));
                 });
  pipeline.drain();
}

// Whether each building is also labelled from its own views.
bool SceneLabeller::labels_per_building() {
  if (job_.per_building == PerBuilding::Off) return false;
  buildings_ = find_buildings(scene_);
  // Auto: only files whose names say they hold buildings; a model whose
  // 1,000 groups are just parts (no '/') is one building, not 1,000.
  return job_.per_building == PerBuilding::On || buildings_.named >= 2;
}

// Per building: views framed on each building (or group of neighbours),
// counting its own triangles.
void SceneLabeller::label_buildings() {
  const BuildingTriangles bt = building_triangles(scene_, buildings_);
  const LabelUnits units = label_units(bt, job_.up, job_.group_span, job_.distance);
  res_.report.per_building = true;
  // Buildings alone share nothing: each counts only its own triangles, from
  // renders of itself, so several threads can label them at once and the
  // labels are the ones one thread gives. Groups and own views in place
  // draw on the district's renderer: one after another.
  const bool all_alone = job_.own_views_alone && std::all_of(units.members.begin(), units.members.end(),
                                                             [](const auto& m) { return m.size() == 1; });
  const size_t lanes = all_alone ? std::min<size_t>(building_lanes(job_), units.members.size()) : 1;
  label_buildings_in_lanes(units, bt, std::max<size_t>(lanes, 1));
}

// The units' own views on `lanes` threads (this one and lanes - 1 more),
// each taking the next unit when it is done with one: each its own OpenGL
// context for buildings alone, tracer and pipeline. With more than one lane
// every unit is a building alone, so their counts go to disjoint triangles;
// the report lists the units in model order.
void SceneLabeller::label_buildings_in_lanes(const LabelUnits& units, const BuildingTriangles& bt, size_t lanes) {
  const size_t n = units.members.size();
  std::vector<BuildingLabelling> entries(n);
  std::atomic<size_t> next{0};
  std::mutex lock;  // progress, the report's step times, the first error
  size_t done = 0;
  std::exception_ptr error;
  auto run_lane = [&](AloneLane& lane) {
    try {
      size_t views = 0, first = 0, pixels = 0;
      double seconds = 0;
      OwnViews own;
      std::map<std::string, double> steps;
      ViewPipeline pipeline(job_.overlap, [](size_t, ViewOutcome&) {}, [&](size_t k, ViewOutcome& o) {
        views += own.passes[k - first].pass == 0;
        pixels += o.report.rendered_pixels;
        for (const auto& [key, v] : o.report.seconds) seconds += v, steps[key] += v;
      });
      for (size_t u; (u = next++) < n;) {
        views = 0;
        pixels = 0;
        seconds = 0;
        own = OwnViews{};
        BuildingLabelling entry = label_unit(uint32_t(u), units, bt, pipeline, own, lane);
        first += own.passes.size();
        entry.views = views;
        entry.rendered_pixels = pixels;
        entry.seconds = seconds;
        std::lock_guard<std::mutex> g(lock);
        if (progress_) progress_->building_labelled(done, n, entry);
        ++done;
        entries[u] = std::move(entry);
      }
      std::lock_guard<std::mutex> g(lock);
      for (const auto& [key, v] : steps) res_.report.step_seconds[key] += v;
    } catch (...) {
      next = n;  // the other lanes stop after their building
      std::lock_guard<std::mutex> g(lock);
      if (!error) error = std::current_exception();
    }
  };
  std::vector<AloneLane> more(lanes - 1);
  std::vector<std::thread> threads;
  try {
    for (AloneLane& lane : more)
      threads.emplace_back([&run_lane, &lane] {
        run_lane(lane);
        lane.renderer.reset();  // its OpenGL context ends on the thread that made it
      });
  } catch (...) {  // a thread could not start: the started ones stop after their building
    next = n;
    for (std::thread& t : threads) t.join();
    throw;
  }
  run_lane(lane_);
  for (std::thread& t : threads) t.join();
  if (error) std::rethrow_exception(error);
  for (BuildingLabelling& e : entries) res_.report.buildings.push_back(std::move(e));
}

// View v of the job framed on `box` (the buildings `own` of `boxes`) at
// `distance`, its sampling chosen for a scene of `triangles`: its tiles'
// passes and names appended to `out`, its samplings and eyes inside
// another building counted there; returns how many tiles.
size_t SceneLabeller::add_framed_view(const Bounds& box, const std::vector<uint32_t>& own,
                                      const std::vector<Bounds>& boxes, size_t v, double distance, size_t triangles,
                                      OwnViews& out) {
  const std::vector<ViewTile> tiles = frame_view(box, job_.up, job_.views[v], distance, job_.display);
  for (const ViewTile& tile : tiles) {
    if (!out.alone) out.eyes_inside += eye_inside_other(tile.camera, boxes, own);
    // The sampling is chosen on the window a view in place has, whose work
    // it estimates; a view of the building alone draws the narrower window
    // (perception_window's `alone`), and samples as the wider one would.
    const Camera window = perception_window(tile.camera, box, ps_);
    const ViewSampling vs = sampling_of(job_, tile.camera, window, triangles, box);
    if (automatic_) ++out.chosen[sampling_name(vs)];
    // Only the window is drawn and read, with the whole frame's projection:
    // a camera cropped to it moves the rasteriser's rounding (the Delft
    // tile's labels at 56 m: 14,695 triangles' counts and 66 labels
    // changed). Its perception equals the whole frame's over the box, so
    // the labels are the whole frame's, as long as every pixel whose
    // samples can hit the box (box_rect) lies in it.
    PixelRect part;
    if (out.window) {
      const PixelRect w = window_rect(tile.camera, box, ps_, out.alone), r = box_rect(tile.camera, box);
      if (inside(r, w)) part = w;
    }
    add_view_passes(out.names.size(), tile.camera, out.alone ? perception_window(tile.camera, box, ps_, true) : window,
                    vs, out.passes, part);
    out.names.push_back(tile.name);
  }
  return tiles.size();
}

// One building's own views, or a group's, through `pipeline` (its passes in
// `own`); returns its report entry, views and seconds left to the caller.
BuildingLabelling SceneLabeller::label_unit(uint32_t u, const LabelUnits& units, const BuildingTriangles& bt,
                                            ViewPipeline& pipeline, OwnViews& own, AloneLane& lane) {
  const std::vector<uint32_t>& members = units.members[u];
  const bool group = members.size() > 1;
  const bool alone = job_.own_views_alone && !group;
  // A building alone is a scene of its own triangles: its views sample as
  // they ask (choose_sampling), not as the district's would.
  const size_t triangles = alone ? bt.triangles[members.front()].size() : nt_;
  own.alone = alone;
  own.window = !group && job_.own_views_window_only;
  GroupViews gv;
  for (size_t v = 0; v < job_.views.size(); ++v) {
    const size_t tiles = add_framed_view(units.box[u], members, bt.box, v, units.distance[u], triangles, own);
    gv.view_of.insert(gv.view_of.end(), tiles, v);
  }
  BuildingLabelling entry;
  entry.building = buildings_.names[members.front()];
  entry.buildings = members.size();
  if (alone) count_alone(members.front(), bt, own, 0, pipeline, lane);
  if (!alone && !group) count_in_place(units.owner, u, units.box[u], own, 0, pipeline);
  if (group) {
    count_group(u, units, bt, pipeline, own, gv);
    settle_group(u, units, bt, gv, pipeline, own, entry, lane);
  }
  entry.eyes_inside_other_buildings = own.eyes_inside;
  entry.sampling_chosen = own.chosen;
  return entry;
}

// A group's views: each keeps its counts of the group's triangles
// (gv.kept, in the order of gv.tris) and how well it saw each member
// (gv.sight) until every view is in (settle_group).
void SceneLabeller::count_group(uint32_t u, const LabelUnits& units, const BuildingTriangles& bt,
                                ViewPipeline& pipeline, const OwnViews& own, GroupViews& gv) {
  const std::vector<uint32_t>& members = units.members[u];
  for (uint32_t b : members) gv.tris.insert(gv.tris.end(), bt.triangles[b].begin(), bt.triangles[b].end());
  std::sort(gv.tris.begin(), gv.tris.end());  // model order
  gv.kept.resize(own.passes.size());
  gv.sight.resize(own.names.size());
  for (size_t k = 0; k < own.passes.size(); ++k) {
    const ViewPass& vp = own.passes[k];
    pipeline.add([&](ViewOutcome& o) { see_view(renderer_, ps_, vp.camera, true, o, vp.grid()); },
                 [&, k](ViewOutcome& o) {
                   count_view(scene_, tracer_, nullptr, job_, vp.sampling, own.names[vp.tile], vp.camera,
                              &units.owner, u, &units.box[u], nullptr, nullptr, o);
                   TriangleCounts& kept = gv.kept[k];
                   kept.traced.resize(gv.tris.size());
                   kept.imperceptible.resize(gv.tris.size());
                   for (size_t i = 0; i < gv.tris.size(); ++i) {
                     kept.traced[i] = o.counts.traced[gv.tris[i]];
                     kept.imperceptible[i] = o.counts.imperceptible[gv.tris[i]];
                   }
                   if (vp.pass) return;
                   const Camera drawn = kept_picture_camera(vp.camera, vp.grid());
                   for (uint32_t b : members)
                     gv.sight[vp.tile].push_back(member_sight(drawn, o.image, bt.box[b], bt.owner, b));
                 });
  }
  pipeline.drain();
}

// Own views in place (own.passes from `from` on): the whole model drawn,
// counting the triangles of `owner[t] == unit`, traced where `box` lies.
void SceneLabeller::count_in_place(const std::vector<uint32_t>& owner, uint32_t unit, const Bounds& box,
                                   const OwnViews& own, size_t from, ViewPipeline& pipeline) {
  for (size_t k = from; k < own.passes.size(); ++k) {
    const ViewPass& vp = own.passes[k];
    pipeline.add([&](ViewOutcome& o) { see_view(renderer_, ps_, vp.camera, depth_, o, vp.grid(), vp.part); },
                 [&](ViewOutcome& o) {
                   count_view(scene_, tracer_, nullptr, job_, vp.sampling, own.names[vp.tile], vp.camera, &owner,
                              unit, &box, &res_, &acc_, o);
                 });
  }
  pipeline.drain();
}

// A building's own views of it alone (job.own_views_alone), own.passes from
// `from` on: rendered, perceived and traced as a scene of its own
// triangles, so nothing else stands in front of or beside it; its counts
// go to its triangles of the model.
void SceneLabeller::count_alone(uint32_t building, const BuildingTriangles& bt, const OwnViews& own, size_t from,
                                ViewPipeline& pipeline, AloneLane& lane) {
  const BuildingAlone alone = building_alone(scene_, bt.triangles[building], lane.vertex);
  if (!lane.renderer) lane.renderer = std::make_unique<Renderer>();
  lane.renderer->set_scene(alone.scene);
  const OctreeTracer tracer(alone.scene);
  const std::vector<uint32_t> all_one(alone.triangle.size(), 0);  // every triangle of it is the building's
  for (size_t k = from; k < own.passes.size(); ++k) {
    const ViewPass& vp = own.passes[k];
    pipeline.add([&](ViewOutcome& o) { see_view(*lane.renderer, ps_, vp.camera, depth_, o, vp.grid(), vp.part); },
                 [&](ViewOutcome& o) {
                   count_view(alone.scene, tracer, nullptr, job_, vp.sampling, own.names[vp.tile], vp.camera,
                              &all_one, 0, &bt.box[building], nullptr, nullptr, o);
                   add_part_counts(alone.scene, alone.triangle, job_, vp.sampling, vp.camera, o.counts, res_, acc_);
                 });
  }
  pipeline.drain();
}

// A group's views counted: each member's counts come from the group's
// views in the directions where they saw it well (MemberSight, at most
// kHiddenShareLimit hidden), and from views framed on it (as without
// groups; alone with job.own_views_alone) in the others, appended to `own`.
void SceneLabeller::settle_group(uint32_t u, const LabelUnits& units, const BuildingTriangles& bt,
                                 const GroupViews& gv, ViewPipeline& pipeline, OwnViews& own,
                                 BuildingLabelling& entry, AloneLane& lane) {
  const std::vector<uint32_t>& members = units.members[u];
  const size_t nv = job_.views.size(), nm = members.size();
  std::vector<MemberSight> seen(nm * nv);  // member j in direction v: [j * nv + v]
  for (size_t tile = 0; tile < gv.sight.size(); ++tile)
    for (size_t j = 0; j < nm; ++j) {
      seen[j * nv + gv.view_of[tile]].own += gv.sight[tile][j].own;
      seen[j * nv + gv.view_of[tile]].hidden += gv.sight[tile][j].hidden;
    }
  std::vector<uint8_t> alone(nm * nv);
  for (size_t i = 0; i < alone.size(); ++i)
    alone[i] = double(seen[i].hidden) > kHiddenShareLimit * double(seen[i].own + seen[i].hidden);
  // The group's views: each adds the counts of the members it saw well.
  const std::vector<uint32_t>& tris = gv.tris;
  std::vector<uint32_t> member_of(tris.size());
  for (size_t i = 0; i < tris.size(); ++i)
    member_of[i] = uint32_t(std::lower_bound(members.begin(), members.end(), bt.owner[tris[i]]) - members.begin());
  std::vector<uint32_t> skip(nt_, 1);  // 0: this view's count of the triangle is added
  TriangleCounts full{std::vector<uint32_t>(nt_, 0), std::vector<uint32_t>(nt_, 0)};
  for (size_t k = 0; k < gv.kept.size(); ++k) {
    const ViewPass& vp = own.passes[k];
    for (size_t i = 0; i < tris.size(); ++i) {
      skip[tris[i]] = alone[member_of[i] * nv + gv.view_of[vp.tile]];
      full.traced[tris[i]] = gv.kept[k].traced[i];
      full.imperceptible[tris[i]] = gv.kept[k].imperceptible[i];
    }
    add_view_counts(scene_, job_, vp.sampling, vp.camera, &skip, 0, full, label_triangles(full, job_.ratio), res_,
                    acc_);
  }
  // The others: each member framed on its own in the directions the group's
  // views saw it poorly.
  own.alone = job_.own_views_alone;
  own.window = job_.own_views_window_only;
  for (size_t j = 0; j < nm; ++j) {
    const uint32_t b = members[j];
    const size_t from = own.passes.size();
    const size_t triangles = job_.own_views_alone ? bt.triangles[b].size() : nt_;
    for (size_t v = 0; v < nv; ++v)
      if (alone[j * nv + v]) entry.own_views += add_framed_view(bt.box[b], {b}, bt.box, v, job_.distance, triangles, own);
    if (from == own.passes.size()) continue;
    ++entry.members_alone;
    if (job_.own_views_alone)
      count_alone(b, bt, own, from, pipeline, lane);
    else
      count_in_place(bt.owner, b, bt.box[b], own, from, pipeline);
  }
}

// The labels from what every view counted, and the report's totals.
LabelResult SceneLabeller::finish() {
  res_.labels = std::move(acc_.combined);
  // Pooled: the totals hold every view's samples of a triangle (a building's
  // own views count only its own triangles, as combined above), and traced
  // is 0 exactly where every view left it undisplayable.
  if (job_.combine == CombineViews::Pooled) res_.labels = label_triangles(res_.totals, job_.ratio);
  for (size_t t = 0; t < nt_; ++t) {
    if (res_.labels[t] == Label::Undisplayable && !acc_.in_frustum[t]) {
      res_.labels[t] = Label::Imperceptible;  // no view could have seen it: the view set was incomplete
      ++res_.outside_views;
    }
  }
  res_.report.labels = count_labels(res_.labels);
  res_.report.outside_views = res_.outside_views;
  return std::move(res_);
}

}  // namespace

LabelResult label_scene(Renderer& renderer, const Scene& scene, const Tracer& tracer, const LabelJob& asked,
                        LabelProgress* progress, const EmbreeTracer* verify_tracer) {
  return SceneLabeller(renderer, scene, tracer, asked, progress, verify_tracer).run();
}

void write_label_outputs(Renderer& renderer, const Scene& scene, LabelResult& result, const LabelJob& job) {
  LabelFile lf{result.labels, result.totals.traced, result.totals.imperceptible, {}};
  for (const auto& v : result.views) lf.views.emplace_back(v.view, job.distance);
  const int samples = effective_samples(job);
  lf.samples = samples == kAutoSamples ? kAutoCountUnit : samples;  // what a pixel counts in the totals
  lf.has_model = true;
  lf.model_triangles = scene.triangle_count();
  lf.model_hash = model_fingerprint(scene);
  std::string path = job.out.labels(job.distance);
  write_labels(path, lf);
  result.report.labels_file = path;
  result.report.markings_written = true;
  result.report.marking_renders = write_marking_images(renderer, scene, result.labels, result.id_buffers, job);
  result.id_buffers.clear();
}

}  // namespace perclod
