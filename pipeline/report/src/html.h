// The report pages' shared parts (private to perclod_report): reading a
// report where a missing or mistyped key is a blank rather than a throw,
// number and path formatting, the page's style, and SVG line charts.
#pragma once

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "perclod/outputs.h"

namespace perclod::html {

using json = nlohmann::json;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---- reading the report ----------------------------------------------------

// j[key] when j is an object holding it, else nullptr.
const json* member(const json& j, const char* key);
// A number member, NaN when missing or not a number.
double num(const json& j, const char* key);
// A member as text: a string as it is, any other value as its JSON; "" when missing.
std::string str(const json& j, const char* key);
// A member, or an empty object when missing.
const json& sub(const json& j, const char* key);
// An array member, an empty array when missing or not an array.
const json& list(const json& j, const char* key);

// ---- formatting -----------------------------------------------------------

// v with `decimals` decimals, or a dash for NaN.
std::string fixed(double v, int decimals);
// v rounded to a whole number, or a dash for NaN.
std::string count(double v);
// A fraction as a percentage ("1.25&nbsp;%"), or a dash.
std::string percent(double fraction, int decimals = 2);

// The labelling's samples per pixel: the number, or "auto" with what the
// views took, e.g. "auto (16 (grid): 21 views)".
std::string samples_text(const json& lod);

// Shortest form, as in file names: 56, 12.5.
std::string short_number(double v);

// "2.35&nbsp;s", "12.4&nbsp;s", or a dash for no figure.
std::string seconds(double s);

// A path for an href/src: bytes outside a safe set percent-encoded (so '#',
// '?', '%', spaces and non-ASCII survive), then HTML-escaped.
std::string url(const std::string& path);

std::string file_name(const std::string& path);

// A file the pipeline wrote under names.dir, relative to a page in names.dir:
// the path below the directory, else its file name (outputs are flat).
std::string relative(const std::string& path, const OutputNames& names);

// "front_t3" -> "front": a view's tiles are shown together, beside the
// view's near marking.
std::string untiled(const std::string& view);

// The pages' CSS (inline: a page needs no other file).
extern const char* const kStyle;

// <!DOCTYPE html> to <body>, with the title and the style.
std::string page_head(const std::string& title);

// ---- charts -----------------------------------------------------------------

// A few round tick values from lo to hi.
std::vector<double> ticks(double lo, double hi, int want = 5);

// Upper end of an axis from 0: the next tick above `v`.
double nice_max(double v);

// A tick's label: "12k", "1.5M" where the step allows, else the number.
std::string tick_label(double v, double step);

struct Series {
  std::string name, css, colour;
  std::vector<double> y;   // one per x (NaN: no point)
  bool right = false;      // against the right axis
  bool dashed = false;
};

struct Axis {
  std::string label;
  double lo = 0, hi = 1;
  std::string suffix;  // tick label suffix, e.g. "%"
  double scale = 1;    // tick label = value * scale
};

// An SVG line chart of `series` against x (distances in metres): x on a log
// scale when the distances span a factor of 3 or more, one tick per
// distance; each point a <circle class="pt CSS"> with a tooltip.
std::string line_chart(const std::string& id, const std::string& title, const std::vector<double>& x,
                       const std::vector<Series>& series, const Axis& left, const Axis* right,
                       const std::vector<std::pair<std::string, double>>& left_rules = {});

}  // namespace perclod::html
