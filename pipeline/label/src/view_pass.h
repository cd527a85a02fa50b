// The labelling of one view (private to perclod_label): what a view's render,
// perception and trace leave (ViewOutcome), the two halves that make it
// (see_view on the thread that owns the OpenGL context, count_view on any),
// the pipeline that overlaps them, and how a view is split into passes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <future>
#include <optional>
#include <string>
#include <vector>

#include "perclod/label.h"
#include "perclod/worker.h"

namespace perclod::detail {

// Per-triangle state over the views of one distance: the labels combined so
// far (combine_labels) and whether any view's frustum held the triangle.
struct Accumulator {
  std::vector<Label> combined;
  std::vector<uint8_t> in_frustum;
  explicit Accumulator(size_t nt) : combined(nt, Label::Undisplayable), in_frustum(nt) {}
};

// Pixels [x, x + w) x [y, y + h) of a camera's image.
struct PixelRect {
  int x = 0, y = 0, w = 0, h = 0;
};
// Whether every pixel of `r` lies in `outer` (both of one frame).
inline bool inside(const PixelRect& r, const PixelRect& outer) {
  return r.x >= outer.x && r.y >= outer.y && r.x + r.w <= outer.x + outer.w && r.y + r.h <= outer.y + outer.h;
}

struct ViewOutcome {
  // The part of the camera's frame that image (and so perception, the
  // traced samples and background) holds; w = 0: the whole frame
  // (held_part gives it either way).
  PixelRect part;
  PerceptionResult perception;
  std::vector<uint8_t> background;
  RenderOutput image;
  std::vector<std::vector<uint32_t>> samples;  // the traced samples, kept for the slot's next view
  std::vector<uint8_t> packed_ids;             // image.ids packed, for a marking image
  // With an ordered grid of samples (sample_grid): the render at grid times
  // the resolution, and of its sample pictures 1.. what counting reads, the
  // ID buffer and the mask (image and perception above are sample 0's);
  // each picture is split and perceived in the scratch buffers.
  RenderOutput fine, scratch;
  PerceptionResult scratch_perception;
  std::vector<uint8_t> scratch_background;
  std::vector<std::vector<uint32_t>> more_ids;
  std::vector<std::vector<uint8_t>> more_masks;
  double t_render = 0, t_perceive = 0;
  ViewLabelling report;
  TriangleCounts counts;  // count_view's, when given nowhere to add them
};

// Labels views one after another with the two halves overlapped: while a
// worker thread traces and counts view k, the calling thread (which owns the
// OpenGL context) renders and perceives view k+1. One view is in flight at a
// time and the counts are added in view order, so the result is the one a
// sequential run gives, bit for bit. seen(k, outcome) runs on the calling
// thread once view k is rendered and perceived (its ID buffer still in use),
// counted(k, outcome) once it is also traced.
class ViewPipeline {
 public:
  using Step = std::function<void(size_t, ViewOutcome&)>;
  ViewPipeline(bool overlap, Step seen, Step counted) : seen_(std::move(seen)), counted_(std::move(counted)) {
    if (overlap) worker_.emplace();
  }
  template <class See, class Count>
  void add(See see, Count count) {
    ViewOutcome& o = slot_[next_ % 2];
    see(o);
    seen_(next_, o);
    drain();
    if (worker_) {
      pending_ = worker_->submit([count, &o] { count(o); });
    } else {
      count(o);
      counted_(next_, o);
    }
    ++next_;
  }
  void drain() {  // waits for the view in flight and hands it over
    if (!pending_.valid()) return;
    pending_.get();
    counted_(next_ - 1, slot_[(next_ - 1) % 2]);
  }

 private:
  Step seen_, counted_;
  ViewOutcome slot_[2];
  size_t next_ = 0;
  // After the slots: an exception ends the worker (finishing the count in
  // flight) before the slot it counts is freed.
  std::optional<Worker> worker_;
  std::future<void> pending_;
};

// The part of `cam`'s frame that `o`'s image holds.
inline PixelRect held_part(const ViewOutcome& o, const Camera& cam) {
  return o.part.w ? o.part : PixelRect{0, 0, cam.width, cam.height};
}

// The image rectangle [lo, hi] (pixel coordinates, unclipped) around the
// projections of `box`'s corners; false when a corner is not in front of
// the eye (not beyond znear when `past_near`).
bool projected_extent(const Camera& cam, const Bounds& box, bool past_near, double lo[2], double hi[2]);

// The pixels of `cam` whose samples can hit something inside `box`: the
// rectangle around its corners' projections, widened by two pixels for the
// sample offsets and rounding; the whole image when a corner is behind the
// eye (an empty rectangle when the box projects outside the image).
PixelRect box_rect(const Camera& cam, const Bounds& box);

// The part of `cam`'s frame perception_window keeps around `box` (the
// whole frame when a box corner is behind the eye).
PixelRect window_rect(const Camera& cam, const Bounds& box, const PerceptionSettings& ps, bool alone = false);

// One render of a view to label: pass `pass` of the view's `passes`
// (its first stands for the view in the records, images and report).
struct ViewPass {
  size_t tile = 0;  // index into the job's tiles (or a building's)
  size_t pass = 0, passes = 1;
  Camera camera;     // what see_view renders (a grid's: before refining)
  ViewSampling sampling;
  PixelRect part;    // of camera's frame, the part see_view draws and reads (w = 0: all)
  int grid() const { return sample_grid(sampling.samples); }
};

// With samples auto, LabelResult::totals count this many samples a pixel
// (each view's counts times kAutoCountUnit / its samples).
constexpr int kAutoCountUnit = 16;

// Whether labelling runs add_unsampled_surface (and so renders depth).
inline bool finds_unsampled_surface(const LabelJob& job) { return job.samples > 1 && job.keep_unsampled_surface; }

// The camera of a view's kept picture (out.image): `cam`, or for a grid of
// samples (grid >= 2) sample 0's picture of it.
Camera kept_picture_camera(Camera cam, int grid);

// The first half of labelling a view, on the thread that owns the OpenGL
// context: render and perceive one camera (only `part` of its frame, when
// given: out.part). grid >= 2: render it at grid times the resolution and
// perceive each of the grid x grid sample pictures.
void see_view(Renderer& renderer, const PerceptionSettings& ps, const Camera& cam, bool want_depth, ViewOutcome& out,
              int grid = 0, const PixelRect& part = {});

// The second half, on any thread: trace the view seen by see_view at
// vs.samples samples per pixel (with vs.mask_per_sample, `cam` is one
// sample pass, traced at its pixel centres); adds its counts and labels for
// the triangles of `owner[t] == building` (all when `owner` is null) to
// `res` and `acc`. With `own_box` (the building's box) only the pixels where
// that box projects are traced: no other sample can hit the building. With
// `res` and `acc` null the counts are left in out.counts for the caller to
// add (add_view_counts) instead.
void count_view(const Scene& scene, const Tracer& tracer, const EmbreeTracer* reference, const LabelJob& job,
                const ViewSampling& vs, const std::string& name, const Camera& cam,
                const std::vector<uint32_t>* owner, uint32_t building, const Bounds* own_box, LabelResult* res,
                Accumulator* acc, ViewOutcome& out);

// Adds one view's counts of the triangles of `owner[t] == building` (all
// when `owner` is null) to the totals, their labels (from `labels`) to the
// combined ones, and the view's frustum to the triangles some view could see.
void add_view_counts(const Scene& scene, const LabelJob& job, const ViewSampling& vs, const Camera& cam,
                     const std::vector<uint32_t>* owner, uint32_t building, const TriangleCounts& counts,
                     const std::vector<Label>& labels, LabelResult& res, Accumulator& acc);

// add_view_counts for a view of `part`, a scene of some of the model's
// triangles (its triangle i is the model's triangle[i]): its counts, their
// labels and its frustum go to those triangles of the model.
void add_part_counts(const Scene& part, const std::vector<uint32_t>& triangle, const LabelJob& job,
                     const ViewSampling& vs, const Camera& cam, const TriangleCounts& counts, LabelResult& res,
                     Accumulator& acc);

// How a view of camera `cam` is sampled: the job's samples, or with
// kAutoSamples the choice for its window on the model (`window`,
// perception_window), the model's `triangles` and the pixels its `box`
// covers (box_rect).
ViewSampling sampling_of(const LabelJob& job, const Camera& cam, const Camera& window, size_t triangles,
                         const Bounds& box);

// The renders of one view of camera `cam`, whose window on the model is
// `window`: one that every sample reads (the whole frame, or with `part` only
// that part of it; a grid's is the window at grid times the resolution), or
// with a mask per sample one render of the window per sample offset, its
// camera shifted by it. Appended to `out`.
void add_view_passes(size_t tile, const Camera& cam, const Camera& window, const ViewSampling& vs,
                     std::vector<ViewPass>& out, const PixelRect& part = {});

std::string sampling_name(const ViewSampling& vs);
// Adds a later pass's timings to the report of the view's first pass.
void add_pass_report(ViewLabelling& first, const ViewLabelling& pass, size_t passes);

}  // namespace perclod::detail
