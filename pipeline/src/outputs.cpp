// Output file names and atomic writes (perclod/outputs.h).
#include "perclod/outputs.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace perclod {
namespace fs = std::filesystem;

std::string distance_tag(double d) {
  std::ostringstream ss;
  ss << d << "m";
  return ss.str();
}

OutputNames output_names_for(const std::string& dir, const std::string& input) {
  return {dir, fs::path(input).stem().string()};
}

std::string OutputNames::file(const std::string& suffix) const { return dir + "/" + stem + suffix; }

std::string OutputNames::view(const std::string& view, double d, const std::string& suffix) const {
  return file("_" + view + "_" + distance_tag(d) + suffix);
}

std::string OutputNames::labels(double d) const { return file("_labels_" + distance_tag(d) + ".txt"); }

std::string OutputNames::label_report(double d) const { return file("_label_" + distance_tag(d) + ".json"); }

std::string OutputNames::lod(double d, const std::string& format) const {
  return file("_lod_" + distance_tag(d) + "." + format);
}

std::string OutputNames::report() const { return file("_report.json"); }

void write_atomic(const std::string& path, const std::function<void(const std::string& temp)>& write) {
  fs::path p(path);
  const std::string tmp = (p.parent_path() / (".tmp-" + p.filename().string())).string();
  std::error_code ec;
  try {
    write(tmp);
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot move the finished file into place");
  }
}

void write_text_atomic(const std::string& path, const std::string& text) {
  write_atomic(path, [&](const std::string& tmp) {
    std::ofstream f(tmp, std::ios::binary);
    if (!f) throw std::runtime_error(path + ": cannot open for writing");
    f.write(text.data(), std::streamsize(text.size()));
    if (!f.flush()) throw std::runtime_error(path + ": write failed (disk full?)");
  });
}

void ensure_directory(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw std::runtime_error(dir + ": cannot create directory");
}

}  // namespace perclod
