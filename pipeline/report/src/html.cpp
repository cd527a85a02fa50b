// Reading reports, formatting figures and paths, the page style (html.h).
#include "html.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string_view>
#include <vector>

namespace perclod::html {

const json* member(const json& j, const char* key) {
  if (!j.is_object()) return nullptr;
  auto it = j.find(key);
  return it == j.end() || it->is_null() ? nullptr : &*it;
}

double num(const json& j, const char* key) {
  const json* v = member(j, key);
  return v && v->is_number() ? v->get<double>() : kNaN;
}

std::string str(const json& j, const char* key) {
  const json* v = member(j, key);
  if (!v) return "";
  return v->is_string() ? v->get<std::string>() : v->dump();
}

const json& sub(const json& j, const char* key) {
  static const json empty = json::object();
  const json* v = member(j, key);
  return v ? *v : empty;
}

const json& list(const json& j, const char* key) {
  static const json empty = json::array();
  const json* v = member(j, key);
  return v && v->is_array() ? *v : empty;
}

std::string fixed(double v, int decimals) {
  if (!std::isfinite(v)) return "&ndash;";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string count(double v) {
  if (!std::isfinite(v)) return "&ndash;";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.0f", v);
  return buf;
}

std::string percent(double fraction, int decimals) {
  return std::isfinite(fraction) ? fixed(100 * fraction, decimals) + "&nbsp;%" : "&ndash;";
}

std::string samples_text(const json& lod) {
  const json* v = member(lod, "samples_per_pixel");
  if (!v) return "&ndash;";
  if (v->is_number()) return count(v->get<double>());
  std::string text = html_escape(str(lod, "samples_per_pixel"));
  const json* chosen = member(lod, "sampling_chosen");
  if (chosen && chosen->is_object() && !chosen->empty()) {
    std::string parts;
    for (const auto& [name, n] : chosen->items())
      parts += (parts.empty() ? "" : ", ") + html_escape(name) + ": " + (n.is_number() ? count(n.get<double>()) : "?") + " views";
    text += " (" + parts + ")";
  }
  return text;
}

std::string short_number(double v) {
  std::ostringstream ss;
  ss << v;
  return ss.str();
}

std::string seconds(double s) { return std::isfinite(s) ? fixed(s, s < 10 ? 2 : 1) + "&nbsp;s" : "&ndash;"; }

// A path for an href/src: bytes outside a safe set percent-encoded (so '#',
// '?', '%', spaces and non-ASCII survive), then HTML-escaped.
std::string url(const std::string& path) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  for (unsigned char c : path) {
    if (std::isalnum(c) || std::string_view("-._~/+,=@").find(char(c)) != std::string_view::npos) {
      out += char(c);
    } else {
      out += '%';
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return html_escape(out);
}

std::string file_name(const std::string& path) { return std::filesystem::path(path).filename().string(); }

// A file the pipeline wrote under names.dir, relative to a page in names.dir:
// the path below the directory, else its file name (outputs are flat).
std::string relative(const std::string& path, const OutputNames& names) {
  const std::string prefix = names.dir + "/";
  if (!names.dir.empty() && path.rfind(prefix, 0) == 0 && path.find("..") == std::string::npos)
    return path.substr(prefix.size());
  return file_name(path);
}

std::string untiled(const std::string& view) {
  const size_t p = view.rfind("_t");
  if (p == std::string::npos || p + 2 == view.size()) return view;
  for (size_t i = p + 2; i < view.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(view[i]))) return view;
  return view.substr(0, p);
}

const char* const kStyle = R"(
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,"DejaVu Sans",sans-serif;margin:24px;color:#1d1d1f;background:#fff;max-width:1240px}
h1{font-size:1.6em;margin:0 0 4px}h2{font-size:1.3em;margin:32px 0 8px;border-bottom:2px solid #d0d7de;padding-bottom:4px}
h3{font-size:1.05em;margin:18px 0 6px}
table{border-collapse:collapse;margin:6px 0 12px;font-size:0.9em}
th,td{border:1px solid #d0d7de;padding:3px 8px;text-align:right}
th{background:#f3f5f7}td.l,th.l{text-align:left}
td.over{background:#ffd7d5;color:#a40e26;font-weight:600}
tr.failed td{background:#fff0ef}tr.skipped td{color:#6e7781}
.muted{color:#6e7781}.warn{color:#a40e26}
.facts td:first-child{text-align:left;font-weight:600;background:#f8f9fa}
figure{display:inline-block;margin:4px 8px 12px 0;vertical-align:top}
figure img{display:block;max-width:200px;max-height:200px;border:1px solid #d0d7de;background:#eee}
figcaption{font-size:0.8em;color:#444;max-width:200px;word-break:break-all}
.pair{display:inline-block;border:1px solid #d0d7de;padding:6px;margin:0 8px 8px 0}
.swatch{display:inline-block;width:12px;height:12px;vertical-align:middle;margin-right:4px;border:1px solid #888}
svg{background:#fff;border:1px solid #d0d7de;margin:4px 8px 8px 0}
svg text{font-family:inherit;font-size:12px;fill:#1d1d1f}
svg .grid{stroke:#e6e9ec}svg .axis{stroke:#57606a}
)";

std::string page_head(const std::string& title) {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
         "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>" +
         html_escape(title) + "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n";
}

}  // namespace perclod::html
