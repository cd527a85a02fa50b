// perclod/report_html.h - the run report as an offline HTML page, and a batch index.
//
// Pages are self-contained: inline CSS, inline SVG charts drawn here, no
// script and no network. Images are referenced by file name relative to the
// page, which lives in the output directory beside them, so an output
// directory can be copied or zipped and still be read in a browser.
//
// model_report_html reads the report make_lods returns (and writes to
// OutputNames::report()) and shows only images the pipeline writes:
//  * per labelling view (each tile) the render <stem>_<view>_<d>m.png, and
//    per view the marking renders the report's "marking_renders" lists
//    (_marking.png, _marking_near.png);
//  * per judged view (labelling and held-out) the picture make_lods writes
//    and names in the view's "comparison_image": original | LOD | changes,
//    captioned with the view's figures.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "perclod/outputs.h"

namespace perclod {

// Text for HTML element content and attribute values: & < > " ' escaped.
std::string html_escape(const std::string& text);

// The page of one model's run report (`report` as make_lods returns it; the
// "model" key `perclod run` adds is used for the title when present, else
// names.stem). Image files are named by `names` and referenced relative to
// names.dir.
std::string model_report_html(const nlohmann::json& report, const OutputNames& names);

// Writes model_report_html to names.report_html() (atomically).
void write_model_report_html(const nlohmann::json& report, const OutputNames& names);

// The index page of a batch of runs. `summary`:
//   {"models": [{"name", "status": "done"|"skipped"|"failed", "error" (failed),
//                "dir" (the model's output dir, relative to the index),
//                "report_html" (relative to the index; absent: no link),
//                "seconds", "lods": [{"distance", "triangles",
//                "worst": {"changed_fraction", "ssim_covered", "silhouette_mismatch"}}]}],
//    "done", "skipped", "failed", "seconds"}
// Missing keys show as blanks; a failed model shows its error.
std::string batch_index_html(const nlohmann::json& summary);

}  // namespace perclod
