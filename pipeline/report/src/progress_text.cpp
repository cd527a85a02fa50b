// The progress lines (perclod/progress_text.h): one per event, worded as
// `perclod` has always printed them.
#include "perclod/progress_text.h"

#include <chrono>
#include <cstdio>
#include <iomanip>
#include <sstream>

namespace perclod {

std::string tracer_summary(const Tracer& tracer) {
  char line[160];
  std::snprintf(line, sizeof line, "%s built in %.0f ms, %zu KiB", tracer.name(), tracer.build_seconds() * 1e3,
                tracer.memory_bytes() / 1024);
  return line;
}

void TextProgress::tracer_built(const Tracer& tracer) { say(tracer_summary(tracer)); }

void TextProgress::view_labelled(const std::string& view, double distance, const ViewLabelling& v) {
  std::ostringstream ss;
  ss.precision(3);
  const auto seconds = [&](const char* step) {
    const auto it = v.seconds.find(step);
    return it == v.seconds.end() ? 0.0 : it->second;
  };
  ss << "  " << view << " at " << distance << " m: " << size_t(v.covered_pixels) << " px, "
     << 100 * v.imperceptible_fraction << "% imperceptible";
  if (v.passes) ss << " in the first of " << v.passes << " passes; all passes:";
  else ss << ";";
  ss << " render " << 1e3 * seconds("render") << " ms, perceive " << 1e3 * seconds("perceive") << " ms, trace "
     << 1e3 * seconds("trace") << " ms";
  if (!v.sampling.empty()) ss << " (samples " << v.sampling << ")";  // auto's choice
  say(ss.str());
}

void TextProgress::building_labelled(size_t index, size_t count, const BuildingLabelling& b) {
  std::ostringstream ss;
  ss.precision(3);
  const auto now = std::chrono::steady_clock::now();
  if (index == 0) buildings_started_ = now;
  if (b.buildings > 1)
    ss << "  group " << index + 1 << "/" << count << " (" << b.buildings << " buildings from " << b.building << ")";
  else
    ss << "  building " << index + 1 << "/" << count << " " << b.building;
  ss << ": " << b.views << " views, " << b.seconds << " s";
  if (b.own_views)
    ss << " (" << b.own_views << " of them framed on one of " << b.members_alone
       << " buildings the group's views saw poorly)";
  if (b.eyes_inside_other_buildings)
    ss << "; " << b.eyes_inside_other_buildings << " with the eye inside another building's box";
  // Time left from the pace since the first one (which it does not count).
  if (index > 0 && index + 1 < count) {
    const double spent = std::chrono::duration<double>(now - buildings_started_).count();
    ss << " (about " << format_seconds(spent / double(index) * double(count - index - 1)) << " left)";
  }
  say(ss.str());
}

void TextProgress::building_judged(size_t k, size_t n, const BuildingJudged& b, double max_visible) {
  std::ostringstream ss;
  ss.precision(2);
  const auto now = std::chrono::steady_clock::now();
  if (k == 0) judging_started_ = now;
  double worst = 0;
  for (const ViewFigures& v : b.views) worst = std::max(worst, v.visible_ratio);
  ss << "  judged " << k + 1 << "/" << n << " " << b.building << " alone: " << b.lod_triangles << " of "
     << b.triangles << " triangles, ";
  if (b.unchanged) ss << "unchanged (its LOD is the original)";
  else ss << b.views.size() << " views, worst visible " << worst << "x the floor";
  if (max_visible > 0 && worst > max_visible) ss << " (over " << max_visible << ")";
  if (k > 0 && k + 1 < n) {
    const double spent = std::chrono::duration<double>(now - judging_started_).count();
    ss << " (about " << format_seconds(spent / double(k) * double(n - k - 1)) << " left)";
  }
  say(ss.str());
}

void TextProgress::distance_started(double distance) {
  std::ostringstream ss;
  ss << "distance " << distance << " m";
  say(ss.str());
}

void TextProgress::undisplayable_decided(double exposure, const UndisplayableRule& rule) {
  std::ostringstream ss;
  ss << std::setprecision(3) << "  undisplayable triangles: " << 100 * exposure
     << "% of the pixels between the labelling views -> " << undisplayable_rule_text(rule);
  say(ss.str());
}

void TextProgress::lod_tried(const char* what, double distance, const LodTry& t) {
  std::ostringstream ss;
  ss << "  " << what << " at " << distance << " m: e_imperceptible " << t.e_imperceptible << " px, e_perceptible "
     << t.e_perceptible << " px, undisplayable " << undisplayable_rule_text(t.undisplayable) << " -> " << t.triangles
     << " triangles, worst " << 100 * t.worst.changed_fraction << "% changed, SSIM " << t.worst.ssim_covered
     << ", silhouette " << 100 * t.worst.silhouette_mismatch << "%, visible " << t.worst.visible_ratio
     << "x the floor" << (t.met ? " (met)" : "");
  say(ss.str());
}

void TextProgress::looser_remade() { say("  fidelity target: back to the loosest bounds that met it"); }
void TextProgress::tightening_midway_missed() { say("  tighten to limits: back to the bounds that met them"); }

void TextProgress::tightening_failed() { say("  tighten to limits: none within; the tightest tried is kept"); }

void TextProgress::lod_made(const LodResult& r) {
  const SimplifyStats& st = r.simplify;
  const WorstFigures& w = r.fidelity.worst;
  std::ostringstream ss;
  ss << "  LOD " << r.distance << " m: " << st.total_before() << " -> " << st.total_after() << " triangles ("
     << (st.total_before() ? 100.0 * double(st.total_after()) / double(st.total_before()) : 0.0) << "%); worst of ";
  if (r.buildings_judged)
    ss << r.building_views << " views of " << r.buildings_judged << " buildings judged alone (" << r.buildings_within
       << " within the limits, " << r.buildings_unchanged << " unchanged)";
  else
    ss << r.views.size() << " views";
  ss << ": " << 100 * w.changed_fraction << "% changed, SSIM "
     << w.ssim_covered << ", silhouette " << 100 * w.silhouette_mismatch << "%, visible " << w.visible_ratio
     << "x the floor; " << r.lod_file;
  say(ss.str());
  if (st.refused_counted) {  // explain: true
    std::ostringstream stop;
    stop << "  LOD " << r.distance << " m stopped: " << refused_text(st.refused);
    say(stop.str());
  }
  std::ostringstream times;
  times.precision(3);
  times << "  LOD " << r.distance << " m took " << r.seconds << " s: label " << r.seconds_label << " s";
  if (r.labelling.per_building) times << " (own views " << r.labelling.seconds_buildings << " s)";
  times << ", simplify " << r.seconds_simplify << " s, judge " << r.seconds_compare << " s, export "
        << r.seconds_export << " s";
  say(times.str());
}

void TextProgress::model_loaded(const std::string& model, const Scene& scene) {
  std::ostringstream ss;
  ss << model << ": " << scene.triangle_count() << " triangles, " << scene.component_count() << " components";
  say(ss.str());
}

std::string batch_line(size_t i, size_t total, const std::string& name, const std::string& what,
                       double seconds_left) {
  std::ostringstream ss;
  ss << "[" << i + 1 << "/" << total << " " << name << "] " << what;
  if (seconds_left >= 0) ss << "  (about " << format_seconds(seconds_left) << " left)";
  return ss.str();
}

std::string format_seconds(double s) {
  char buf[32];
  if (s < 90) std::snprintf(buf, sizeof buf, "%.0fs", s);
  else if (s < 5400) std::snprintf(buf, sizeof buf, "%dm%02ds", int(s) / 60, int(s) % 60);
  else std::snprintf(buf, sizeof buf, "%dh%02dm", int(s) / 3600, (int(s) % 3600) / 60);
  return buf;
}

}  // namespace perclod
