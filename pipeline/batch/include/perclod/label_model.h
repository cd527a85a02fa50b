// perclod/label_model.h - `perclod label`: one model labelled at one
// distance, with its labels file, marking renders and label report.
#pragma once

#include "perclod/label.h"
#include "perclod/runtime.h"

namespace perclod {

// label_scene + write_label_outputs with a tracer of `tracer` kind, and the
// report (label_report_json) written to out.label_report(d). Returns the
// report.
LabelReport label_model(const Scene& scene, const LabelJob& job, TracerKind tracer, LabelProgress* progress = nullptr);

}  // namespace perclod
