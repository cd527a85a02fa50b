// The labels file: plain text, one line per triangle (format in labels_io.h).
#include "perclod/labels_io.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "perclod/outputs.h"

namespace perclod {
namespace {

bool parse_hex(const std::string& s, uint64_t& v) {
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v, 16);
  return ec == std::errc() && p == s.data() + s.size();
}

}  // namespace

void write_labels(const std::string& path, const LabelFile& f) {
  size_t n = f.labels.size();
  if (f.traced.size() != n || f.imperceptible.size() != n)
    throw std::invalid_argument("labels: counts and labels differ in length");
  std::string out;
  out.reserve(n * 10 + 256);
  out += "perclod-labels 1\n";
  if (f.has_model) {
    char hash[17];
    std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(f.model_hash));
    out += "model " + std::to_string(f.model_triangles) + " " + hash + "\n";
  }
  out += "triangles " + std::to_string(n) + "\nviews " + std::to_string(f.views.size()) + "\n";
  for (const auto& [name, d] : f.views) {
    std::ostringstream ss;
    ss << "view " << name << " " << d << "\n";
    out += ss.str();
  }
  if (f.samples != 1) out += "samples " + std::to_string(f.samples) + "\n";
  static const char code[3] = {'P', 'I', 'U'};
  for (size_t i = 0; i < n; ++i) {
    out += code[uint8_t(f.labels[i])];
    out += ' ';
    out += std::to_string(f.traced[i]);
    out += ' ';
    out += std::to_string(f.imperceptible[i]);
    out += '\n';
  }
  write_text_atomic(path, out);
}

uint64_t model_fingerprint(const Scene& scene) {
  uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a/64
  auto add = [&](const void* data, size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < bytes; ++i) {
      h ^= p[i];
      h *= 0x100000001b3ull;
    }
  };
  add(scene.positions.data(), scene.positions.size() * sizeof(float));
  add(scene.indices.data(), scene.indices.size() * sizeof(uint32_t));
  return h;
}

namespace {

// The words of a line, split at the characters `>>` skips in the C locale
// (so tabs and a CRLF line end read as before). Not a stream per line: on a
// million-triangle file that was most of read_labels' time.
void split_words(const std::string& line, std::vector<std::string>& w) {
  auto space = [](char c) { return c == ' ' || (c >= '\t' && c <= '\r'); };
  w.clear();
  size_t i = 0;
  while (true) {
    while (i < line.size() && space(line[i])) ++i;
    if (i == line.size()) return;
    size_t j = i;
    while (j < line.size() && !space(line[j])) ++j;
    w.emplace_back(line, i, j - i);
    i = j;
  }
}

// A non-negative decimal integer that fits T (no sign, no garbage).
template <class T>
bool parse_uint(const std::string& s, T& v) {
  if (s.empty() || s[0] == '-' || s[0] == '+') return false;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && p == s.data() + s.size();
}

// A labels file read line by line: the stream, the line number and the words
// of the current line, and the error naming the file and line.
struct LabelLines {
  explicit LabelLines(const std::string& p) : path(p), in(p, std::ios::binary) {}

  const std::string& path;
  std::ifstream in;
  size_t line = 0;
  std::vector<std::string> w;
  std::string s;

  // Reads the next line into w; false at the end of the file.
  bool next() {
    if (!std::getline(in, s)) return false;
    ++line;
    split_words(s, w);
    return true;
  }
  // The error for a line of this file.
  std::runtime_error bad(size_t at, const std::string& what) const {
    return std::runtime_error(path + ":" + std::to_string(at) + ": " + what);
  }
};

// Reads the header up to the views count: the magic line, the optional model
// line and the triangles line (checked against the file's size); returns the
// triangle count.
uint64_t read_counts_header(LabelLines& r, std::error_code ec, uintmax_t file_size, LabelFile& f) {
  auto& w = r.w;
  if (!r.next() || w.size() != 2 || w[0] != "perclod-labels" || w[1] != "1")
    throw r.bad(1, "not a perclod labels file (expected 'perclod-labels 1')");
  if (!r.next()) throw r.bad(r.line + 1, "expected 'triangles N'");
  if (!w.empty() && w[0] == "model") {
    uint64_t triangles = 0;
    if (w.size() != 3 || !parse_uint(w[1], triangles) || w[2].size() != 16 ||
        !parse_hex(w[2], f.model_hash))
      throw r.bad(r.line, "expected 'model TRIANGLES HASH' (HASH: 16 hex digits)");
    f.has_model = true;
    f.model_triangles = triangles;
    if (!r.next()) throw r.bad(r.line + 1, "expected 'triangles N'");
  }
  uint64_t n = 0;
  if (w.size() != 2 || w[0] != "triangles" || !parse_uint(w[1], n))
    throw r.bad(r.line, "expected 'triangles N' (N a non-negative integer)");
  // Every triangle line takes at least 6 bytes ("P 0 0\n"): refuse a count
  // the file cannot hold before allocating for it.
  if (ec == std::error_code() && n > file_size / 6)
    throw r.bad(r.line, "says " + w[1] + " triangles but a file of " + std::to_string(file_size) +
                            " bytes holds at most " + std::to_string(file_size / 6));
  if (f.has_model && f.model_triangles != n)
    throw r.bad(r.line, "the model line says " + std::to_string(f.model_triangles) + " triangles, this line " +
                            std::to_string(n));
  return n;
}

// Reads the views line and its 'view NAME DISTANCE' lines into f.views.
void read_view_lines(LabelLines& r, uintmax_t file_size, LabelFile& f) {
  auto& w = r.w;
  uint64_t views = 0;
  if (!r.next() || w.size() != 2 || w[0] != "views" || !parse_uint(w[1], views))
    throw r.bad(r.line, "expected 'views V'");
  if (views > file_size / 8) throw r.bad(r.line, "says " + w[1] + " views, more than the file can hold");
  for (uint64_t v = 0; v < views; ++v) {
    double d = 0;
    if (!r.next() || w.size() != 3 || w[0] != "view") throw r.bad(r.line, "expected 'view NAME DISTANCE'");
    try {
      size_t used = 0;
      d = std::stod(w[2], &used);
      if (used != w[2].size() || !(d > 0) || !std::isfinite(d)) throw std::invalid_argument("");
    } catch (const std::exception&) {
      throw r.bad(r.line, "the view distance '" + w[2] + "' is not a positive number of metres");
    }
    f.views.emplace_back(w[1], d);
  }
}

// Reads the optional samples line into f.samples; returns whether a line is
// pending (read but not yet consumed: the first triangle's).
bool read_samples_line(LabelLines& r, LabelFile& f) {
  auto& w = r.w;
  bool pending = r.next();  // the optional samples line, or the first triangle's
  if (pending && !w.empty() && w[0] == "samples") {
    uint64_t s = 0;
    if (w.size() != 2 || !parse_uint(w[1], s) || !(s == 2 || s == 4 || s == 8 || s == 9 || s == 16))
      throw r.bad(r.line, "expected 'samples S' with S one of 2, 4, 8, 9, 16");
    f.samples = int(s);
    pending = r.next();
  }
  return pending;
}

// Reads the n triangle lines 'LABEL TRACED IMPERCEPTIBLE' into f (sized to n);
// returns whether the last read found a line.
bool read_triangle_lines(LabelLines& r, uint64_t n, bool pending, LabelFile& f) {
  auto& w = r.w;
  for (size_t i = 0; i < n; ++i) {
    if (i > 0) pending = r.next();
    if (!pending || w.size() != 3 || w[0].size() != 1)
      throw r.bad(r.line, "expected 'LABEL TRACED IMPERCEPTIBLE' (triangle " + std::to_string(i) + " of " +
                              std::to_string(n) + ")");
    if (!parse_uint(w[1], f.traced[i]) || !parse_uint(w[2], f.imperceptible[i]))
      throw r.bad(r.line, "pixel counts must be non-negative integers, got '" + w[1] + " " + w[2] + "'");
    if (f.imperceptible[i] > f.traced[i])
      throw r.bad(r.line, "more imperceptible pixels (" + w[2] + ") than traced ones (" + w[1] + ")");
    char c = w[0][0];
    if (c == 'P') f.labels[i] = Label::Perceptible;
    else if (c == 'I') f.labels[i] = Label::Imperceptible;
    else if (c == 'U') f.labels[i] = Label::Undisplayable;
    else throw r.bad(r.line, "label '" + w[0] + "' is not P, I or U");
  }
  return pending;
}

}  // namespace

LabelFile read_labels(const std::string& path) {
  LabelLines r(path);
  if (!r.in) throw std::runtime_error(path + ": cannot open labels file");
  std::error_code ec;
  const uintmax_t file_size = std::filesystem::file_size(path, ec);
  LabelFile f;
  const uint64_t n = read_counts_header(r, ec, file_size, f);
  read_view_lines(r, file_size, f);
  f.labels.resize(n);
  f.traced.resize(n);
  f.imperceptible.resize(n);
  bool pending = read_samples_line(r, f);
  pending = read_triangle_lines(r, n, pending, f);
  if (n == 0 && pending && !r.w.empty())
    throw r.bad(r.line, "unexpected line after the header of a file of 0 triangles");
  while (r.next())
    if (!r.w.empty()) throw r.bad(r.line, "unexpected line after the " + std::to_string(n) + " triangle lines");
  return f;
}

}  // namespace perclod
