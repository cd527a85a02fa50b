// perclod/lod.h - the whole method for one model: render, perceive, ray-cast,
// label, simplify, export. The CLI's `label` and `run` commands are thin
// wrappers around these two functions.
#pragma once

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "perclod/display.h"
#include "perclod/perception.h"
#include "perclod/raycast.h"
#include "perclod/render.h"
#include "perclod/simplify.h"
#include "perclod/views.h"

namespace perclod {

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
  std::string out_dir;                // "" = write no images
  std::string stem;                   // file name prefix
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

using Progress = std::function<void(const std::string& message)>;

// Labels every triangle of `scene` from the job's facade views at one distance.
// `renderer` must already hold `scene` (Renderer::set_scene).
LabelResult label_scene(Renderer& renderer, const Scene& scene, const Tracer& tracer, const LabelJob& job,
                        const Progress& progress = {});

// Marking-colour renders of `labels` from each facade at `distance` and at
// distance * closer_factor: <out>/<stem>_<facade>_<d>m_marking.png and _marking_near.png.
std::vector<std::string> write_marking_renders(Renderer& renderer, const Scene& scene,
                                               const std::vector<Label>& labels, const LabelJob& job);

// Writes <out>/<stem>_labels_<d>m.txt and the marking renders, and records
// their paths in result.report ("labels_file", "marking_renders").
void write_label_outputs(Renderer& renderer, const Scene& scene, LabelResult& result, const LabelJob& job);

// How a LOD looks from the views it was labelled from: each view is rendered
// from `lod` and run through the same vision simulation as the original; a
// pixel (drawn in either render) has changed when the two simulated images
// differ there by more than the perception threshold. Per view: drawn pixels,
// changed pixels and their fraction, pixels drawn in only one of the two.
// Leaves `lod` in the renderer.
nlohmann::json compare_lod_views(Renderer& renderer, const Scene& lod, const LabelResult& original,
                                 const LabelJob& job);

// SimplifyStats as the reports print them (`run` and `simplify --json`).
nlohmann::json simplify_stats_json(const SimplifyStats& stats);

struct LodJob {
  LabelJob label;                      // facades, display, perception, ratio, out_dir, stem
  std::vector<double> distances;
  TracerKind tracer = TracerKind::Octree;
  SimplifyOptions simplify;            // mode, k, ...; pixel_footprint is set per distance
  std::string lod_format = "obj";      // "obj" or "glb"
};

// One LOD per distance: <out>/<stem>_lod_<d>m.<fmt>, <stem>_labels_<d>m.txt,
// marking renders, and <out>/<stem>_report.json (returned too).
nlohmann::json make_lods(const Scene& scene, const LodJob& job, const Progress& progress = {});

}  // namespace perclod
