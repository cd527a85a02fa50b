// perclod/pipeline.h - the method for one model, as the commands run it.
//
// One library call per command (the CLI only maps options onto these jobs):
//   render_views    perclod render    shaded views, ID and depth buffers
//   label_model     perclod label     render -> perceive -> ray-cast -> labels, marking renders
//   simplify_model  perclod simplify  one LOD from a labels file
//   make_lods       perclod run       label + simplify + judge, one LOD per distance
// and the steps they are made of (label_scene, write_label_outputs,
// compare_lod_views) for tests and benchmarks. Every file they write is named
// by OutputNames (perclod/outputs.h) and written atomically.
#pragma once

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "perclod/display.h"
#include "perclod/labels_io.h"
#include "perclod/outputs.h"
#include "perclod/perception.h"
#include "perclod/raycast.h"
#include "perclod/render.h"
#include "perclod/simplify.h"
#include "perclod/views.h"

namespace perclod {

// Progress lines for stderr (may be empty).
using Progress = std::function<void(const std::string& message)>;

// ---- perclod render -------------------------------------------------------

struct ViewFiles {
  std::string facade;
  double distance = 0;
  std::string color, ids, depth;  // paths written ("" = not requested)
  size_t covered_pixels = 0;      // pixels showing geometry
  double render_seconds = 0;
};

struct RenderViewsJob {
  OutputNames out;
  UpAxis up = UpAxis::Y;
  std::vector<std::string> facades;
  std::vector<double> distances;
  DisplayProfile display;
  bool write_ids = false, write_depth = false;
  ColorBy color_by = ColorBy::Material;
};

// out.view(facade, d, ".png"), plus "_ids.tif" (uint32, triangle index + 1)
// and "_depth.tif" (float eye depth, metres) on request. `progress` (may be
// empty) is called after each view.
std::vector<ViewFiles> render_views(const Scene& scene, const RenderViewsJob& job,
                                    const std::function<void(const ViewFiles&, size_t done, size_t total)>& progress);

// ---- perclod label --------------------------------------------------------

enum class TracerKind { Octree, Embree };
TracerKind parse_tracer(const std::string& s);  // "octree" | "embree"
// The production tracer of that kind (Embree in its fast packet mode).
std::unique_ptr<Tracer> make_tracer(const Scene& scene, TracerKind kind);

struct LabelJob {
  UpAxis up = UpAxis::Y;
  DisplayProfile display;
  PerceptionSettings perception;      // ppd is taken from `display`
  std::vector<std::string> facades;   // e.g. parse_facades("all", up)
  double distance = 56;
  double ratio = 0.5;                 // imperceptible / traced >= ratio -> imperceptible
  bool verify = false;                // also trace with Embree (tie-rule mode) and compare
  double closer_factor = 0.25;        // marking render from d * closer_factor too
  OutputNames out;                    // out.dir "" = write no files
  bool write_perception_images = true;
};

// What one labelling view saw, kept to judge a LOD from the same view.
struct ViewRecord {
  std::string facade;
  Camera camera;
  std::vector<float> simulated;            // vision-simulated luminance of the render
  std::vector<uint8_t> background;         // 1 where no triangle was drawn
};

struct LabelResult {
  std::vector<Label> labels;               // combined over views
  TriangleCounts totals;                   // summed over views
  std::vector<std::vector<Label>> per_view;
  std::vector<ViewRecord> views;           // in job.facades order
  nlohmann::json report;                   // per view: pixels, fractions, agreement, timings
};

// Labels every triangle of `scene` from the job's facade views at one
// distance. Uploads `scene` to `renderer`, where it stays for
// write_label_outputs. Writes the renders and perception images of each view
// when job.out.dir is set.
LabelResult label_scene(Renderer& renderer, const Scene& scene, const Tracer& tracer, const LabelJob& job,
                        const Progress& progress = {});

// Writes out.labels(d) and the marking-colour renders of the combined labels
// from each facade at d and at d * closer_factor (out.view(f, d, "_marking.png"),
// "_marking_near.png"); records their paths in result.report ("labels_file",
// "marking_renders"). `renderer` must hold `scene` (as label_scene leaves it).
void write_label_outputs(Renderer& renderer, const Scene& scene, LabelResult& result, const LabelJob& job);

// label_scene + write_label_outputs with a tracer of `tracer` kind, and the
// report written to out.label_report(d). Returns that report.
nlohmann::json label_model(const Scene& scene, const LabelJob& job, TracerKind tracer,
                           const Progress& progress = {});

// ---- perclod simplify -----------------------------------------------------

struct SimplifyJob {
  std::string labels_file;       // from perclod label; "" only for qem and cluster
  std::string model_file;        // named in errors when the labels belong to another model
  const LabelFile* labels = nullptr;  // already read from labels_file (else simplify_model reads it)
  double distance = 0;           // metres: p(d) for bounded and cluster
  DisplayProfile display;
  SimplifyOptions options;       // pixel_footprint is set from distance and display
  OutputNames out;               // the LOD goes to out.lod(distance, format)
  std::string format = "obj";    // "obj" or "glb"
};

struct SimplifyRun {
  SimplifyStats stats;
  std::string lod_file;
  double pixel_footprint = 0;
  double write_seconds = 0;
};

// Reads and checks the labels against `scene`, simplifies, exports.
SimplifyRun simplify_model(const Scene& scene, const SimplifyJob& job);

// SimplifyStats as the reports print them (`run` and `simplify --json`).
nlohmann::json simplify_stats_json(const SimplifyStats& stats);

// ---- perclod run ----------------------------------------------------------

// How a LOD looks from the views it was labelled from: each view is rendered
// from `lod` and run through the same vision simulation as the original; a
// pixel (drawn in either render) has changed when the two simulated images
// differ there by more than the perception threshold. Per view: drawn pixels,
// changed pixels and their fraction, pixels drawn in only one of the two.
// Uploads `lod` to `renderer`.
nlohmann::json compare_lod_views(Renderer& renderer, const Scene& lod, const LabelResult& original,
                                 const LabelJob& job);

struct LodJob {
  LabelJob label;                      // facades, display, perception, ratio, output names
  std::vector<double> distances;
  TracerKind tracer = TracerKind::Octree;
  SimplifyOptions simplify;            // mode, k, ...; pixel_footprint is set per distance
  std::string lod_format = "obj";      // "obj" or "glb"
};

// One LOD per distance: out.lod(d), out.labels(d), renders and marking
// renders, and out.report() (returned too).
// A LOD without triangles (nothing displayable at its distance) is still
// written; its entry gets "empty": true and the report a "warnings" list
// (absent when there is nothing to warn about) for the caller to print.
nlohmann::json make_lods(const Scene& scene, const LodJob& job, const Progress& progress = {});

}  // namespace perclod
