// A batch's summary as JSON (perclod/batch_summary.h).
#include "perclod/batch_summary.h"

#include "perclod/report_json.h"

namespace perclod {
namespace {

nlohmann::json lod_summary_json(const LodSummary& l) {
  return {{"distance", l.distance},
          {"triangles", l.triangles},
          {"worst", l.worst ? worst_figures_json(*l.worst) : nlohmann::json::object()}};
}

nlohmann::json model_outcome_json(const ModelOutcome& m) {
  nlohmann::json r = {{"name", m.name}, {"model", m.model}, {"dir", m.dir}, {"status", model_status_name(m.status)}};
  if (m.status == ModelStatus::Failed) r["error"] = m.error;
  if (m.status != ModelStatus::Failed) {
    r["lods"] = nlohmann::json::array();
    for (const LodSummary& l : m.lods) r["lods"].push_back(lod_summary_json(l));
  }
  if (!m.report_html.empty()) r["report_html"] = m.report_html;
  if (!m.warnings.empty()) r["warnings"] = m.warnings;
  if (m.status == ModelStatus::Done) r["over_limits"] = m.over_limits;
  r["seconds"] = m.seconds;
  return r;
}

}  // namespace

const char* model_status_name(ModelStatus s) {
  switch (s) {
    case ModelStatus::Done: return "done";
    case ModelStatus::Skipped: return "skipped";
    case ModelStatus::Failed: break;
  }
  return "failed";
}

nlohmann::json batch_summary_json(const BatchSummary& s) {
  nlohmann::json j = {{"models", nlohmann::json::array()},
                      {"done", s.done},
                      {"skipped", s.skipped},
                      {"failed", s.failed},
                      {"shard", s.shard},
                      {"config", s.config},
                      {"perclod_version", s.perclod_version},
                      {"seconds", s.seconds}};
  for (const ModelOutcome& m : s.models) j["models"].push_back(model_outcome_json(m));
  return j;
}

}  // namespace perclod
