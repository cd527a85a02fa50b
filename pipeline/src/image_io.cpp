// Image files through OpenImageIO; atomic writes via temporary file + rename.
#include "perclod/image_io.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace perclod {
namespace fs = std::filesystem;
namespace {

std::runtime_error io_error(const std::string& path, const std::string& what) {
  return std::runtime_error(path + ": " + what);
}

// The temporary keeps the extension so OIIO picks the right format.
std::string temp_path(const std::string& path) {
  fs::path p(path);
  return (p.parent_path() / (".tmp-" + p.filename().string())).string();
}

void commit_temp(const std::string& tmp, const std::string& path) {
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw io_error(path, "cannot move the finished file into place");
  }
}

void write_image(const std::string& path, int w, int h, int channels, OIIO::TypeDesc type,
                 const void* data) {
  if (w <= 0 || h <= 0 || channels < 1 || channels > 4) throw io_error(path, "bad image size");
  std::string tmp = temp_path(path);
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw io_error(path, "no image writer for this extension");
  OIIO::ImageSpec spec(w, h, channels, type);
  if (!out->open(tmp, spec) || !out->write_image(type, data)) {
    std::string err = out->geterror();
    out.reset();
    std::remove(tmp.c_str());
    throw io_error(path, "cannot write image: " + err);
  }
  out->close();
  commit_temp(tmp, path);
}

template <class T>
std::vector<T> read_image(const std::string& path, OIIO::TypeDesc type, int* w, int* h, int* c) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw io_error(path, "cannot read image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  *w = spec.width;
  *h = spec.height;
  *c = spec.nchannels;
  std::vector<T> data(size_t(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, type, data.data()))
    throw io_error(path, "cannot decode image: " + in->geterror());
  return data;
}

}  // namespace

Rgb8Image read_rgb8(const std::string& path) {
  int w, h, c;
  auto raw = read_image<uint8_t>(path, OIIO::TypeDesc::UINT8, &w, &h, &c);
  Rgb8Image img;
  img.width = w;
  img.height = h;
  img.pixels.resize(size_t(w) * h * 3);
  for (size_t i = 0; i < size_t(w) * h; ++i)
    for (int k = 0; k < 3; ++k) img.pixels[3 * i + k] = raw[i * c + (c >= 3 ? k : 0)];
  return img;
}

void write_png(const std::string& path, int w, int h, int channels, const uint8_t* data) {
  write_image(path, w, h, channels, OIIO::TypeDesc::UINT8, data);
}

void write_tiff_float(const std::string& path, int w, int h, int channels, const float* data) {
  write_image(path, w, h, channels, OIIO::TypeDesc::FLOAT, data);
}

void write_tiff_uint32(const std::string& path, int w, int h, const uint32_t* data) {
  write_image(path, w, h, 1, OIIO::TypeDesc::UINT32, data);
}

std::vector<uint32_t> read_tiff_uint32(const std::string& path, int* w, int* h) {
  int c;
  auto v = read_image<uint32_t>(path, OIIO::TypeDesc::UINT32, w, h, &c);
  if (c != 1) throw io_error(path, "expected a one-channel ID image");
  return v;
}

std::vector<float> read_tiff_float(const std::string& path, int* w, int* h, int* c) {
  return read_image<float>(path, OIIO::TypeDesc::FLOAT, w, h, c);
}

void write_text_atomic(const std::string& path, const std::string& text) {
  std::string tmp = temp_path(path);
  {
    std::ofstream f(tmp, std::ios::binary);
    if (!f) throw io_error(path, "cannot open for writing");
    f.write(text.data(), std::streamsize(text.size()));
    if (!f.flush()) {
      std::remove(tmp.c_str());
      throw io_error(path, "write failed (disk full?)");
    }
  }
  commit_temp(tmp, path);
}

void ensure_directory(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw io_error(dir, "cannot create directory");
}

}  // namespace perclod
