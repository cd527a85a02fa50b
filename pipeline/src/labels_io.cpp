// The labels file: plain text, one line per triangle (format in labels_io.h).
#include "perclod/labels_io.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "perclod/outputs.h"

namespace perclod {

void write_labels(const std::string& path, const LabelFile& f) {
  size_t n = f.labels.size();
  if (f.traced.size() != n || f.imperceptible.size() != n)
    throw std::invalid_argument("labels: counts and labels differ in length");
  std::string out;
  out.reserve(n * 10 + 256);
  out += "perclod-labels 1\ntriangles " + std::to_string(n) + "\nviews " + std::to_string(f.views.size()) + "\n";
  for (const auto& [name, d] : f.views) {
    std::ostringstream ss;
    ss << "view " << name << " " << d << "\n";
    out += ss.str();
  }
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

LabelFile read_labels(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open labels file");
  auto bad = [&](size_t line, const std::string& what) {
    return std::runtime_error(path + ":" + std::to_string(line) + ": " + what);
  };
  std::string magic, key;
  int version = 0;
  size_t n = 0, views = 0, line = 1;
  if (!(in >> magic >> version) || magic != "perclod-labels" || version != 1)
    throw bad(1, "not a perclod labels file (expected 'perclod-labels 1')");
  if (!(in >> key >> n) || key != "triangles") throw bad(2, "expected 'triangles N'");
  if (!(in >> key >> views) || key != "views") throw bad(3, "expected 'views V'");
  line = 3;
  LabelFile f;
  for (size_t v = 0; v < views; ++v) {
    std::string name;
    double d;
    ++line;
    if (!(in >> key >> name >> d) || key != "view") throw bad(line, "expected 'view NAME DISTANCE'");
    f.views.emplace_back(name, d);
  }
  f.labels.resize(n);
  f.traced.resize(n);
  f.imperceptible.resize(n);
  for (size_t i = 0; i < n; ++i) {
    char c;
    ++line;
    if (!(in >> c >> f.traced[i] >> f.imperceptible[i])) throw bad(line, "expected 'LABEL TRACED IMPERCEPTIBLE'");
    if (c == 'P') f.labels[i] = Label::Perceptible;
    else if (c == 'I') f.labels[i] = Label::Imperceptible;
    else if (c == 'U') f.labels[i] = Label::Undisplayable;
    else throw bad(line, std::string("label '") + c + "' is not P, I or U");
  }
  return f;
}

}  // namespace perclod
