// perclod/progress_text.h - the progress lines `perclod` prints on stderr,
// from the events the stages tell while they work (LabelProgress,
// LodProgress, ModelProgress), and the lines of a batch.
#pragma once

#include <chrono>

#include <cstddef>
#include <string>

#include "perclod/lods.h"
#include "perclod/runtime.h"

namespace perclod {

// What a one-model run tells besides make_lods' events (run_model).
class ModelProgress : public LodProgress {
 public:
  virtual void model_loaded(const std::string& model, const Scene& scene) = 0;
};

// Every event as one line to `sink`.
class TextProgress final : public ModelProgress {
 public:
  explicit TextProgress(Progress sink) : sink_(std::move(sink)) {}
  void tracer_built(const Tracer& tracer) override;
  void view_labelled(const std::string& view, double distance, const ViewLabelling& v) override;
  void building_labelled(size_t index, size_t count, const BuildingLabelling& b) override;
  void distance_started(double distance) override;
  void undisplayable_decided(double exposure, const UndisplayableRule& rule) override;
  void lod_tried(const char* what, double distance, const LodTry& t) override;
  void looser_remade() override;
  void tightening_midway_missed() override;
  void tightening_failed() override;
  void building_judged(size_t k, size_t n, const BuildingJudged& b, double max_visible) override;
  void lod_made(const LodResult& r) override;
  void model_loaded(const std::string& model, const Scene& scene) override;

 private:
  void say(const std::string& line) const {
    if (sink_) sink_(line);
  }
  Progress sink_;
  std::chrono::steady_clock::time_point buildings_started_;  // when the distance's first building was labelled
  std::chrono::steady_clock::time_point judging_started_;    // or judged alone
};

// "octree built in 120 ms, 4096 KiB": the line after a tracer build.
std::string tracer_summary(const Tracer& tracer);

// A batch's line about model i (from 0) of `total`: "[i+1/total name] what",
// with "  (about 5m20s left)" when seconds_left >= 0.
std::string batch_line(size_t i, size_t total, const std::string& name, const std::string& what,
                       double seconds_left);
// 45s, 12m05s, 2h10m: a duration as the batch lines give it.
std::string format_seconds(double s);

}  // namespace perclod
