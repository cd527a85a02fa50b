// Image files through OpenImageIO, loaded on first use (image_codec.h);
// writes are atomic (perclod/outputs.h).
#include "perclod/image_io.h"

#include <dlfcn.h>

#include <condition_variable>
#include <exception>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <utility>

#include "image_codec.h"
#include "perclod/outputs.h"
#include "perclod/worker.h"

namespace perclod {
namespace detail {

namespace {

// The module's file: beside the running program (a perclod copied elsewhere
// with its module), else where the build wrote it.
std::string image_module_file() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path beside = exe.parent_path() / PERCLOD_IMAGE_MODULE_NAME;
    if (std::filesystem::exists(beside, ec)) return beside.string();
  }
  if (std::filesystem::exists(PERCLOD_IMAGE_MODULE, ec)) return PERCLOD_IMAGE_MODULE;
  throw std::runtime_error(std::string("cannot find perclod's image module ") + PERCLOD_IMAGE_MODULE_NAME +
                           ": it is neither beside " + (exe.empty() ? "the program" : exe.string()) +
                           " nor at " + PERCLOD_IMAGE_MODULE + " (copy it beside perclod, or rebuild)");
}

// dlopen()s the module: RTLD_NOW, so a missing symbol fails here and not in
// the middle of a write; never closed (OpenImageIO keeps threads and caches).
const ImageCodec& load_image_codec() {
  const std::string file = image_module_file();
  void* module = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!module) throw std::runtime_error(std::string("cannot load perclod's image module: ") + dlerror());
  auto entry = reinterpret_cast<ImageCodecEntry>(dlsym(module, kImageCodecEntry));
  if (!entry) throw std::runtime_error(file + ": no " + kImageCodecEntry + " (not perclod's image module)");
  const ImageCodec* codec = entry();
  if (!codec || codec->abi != kImageCodecAbi)
    throw std::runtime_error(file + ": built from another perclod (image module ABI " +
                             std::to_string(codec ? codec->abi : -1) + ", expected " +
                             std::to_string(kImageCodecAbi) + "); rebuild perclod");
  return *codec;
}

}  // namespace

const ImageCodec& image_codec() {
  static const ImageCodec& codec = load_image_codec();  // a failure throws and is retried next call
  return codec;
}

}  // namespace detail

namespace {

void write_image(const std::string& path, int w, int h, int channels, detail::PixelType type, const void* data) {
  const std::vector<unsigned char> bytes = detail::image_codec().encode(path, w, h, channels, type, data);
  write_bytes_atomic(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

template <class T>
std::vector<T> read_image(const std::string& path, detail::PixelType type, int* w, int* h, int* c) {
  std::vector<T> data;
  detail::image_codec().decode(path, type, [&](int width, int height, int channels) -> void* {
    *w = width;
    *h = height;
    *c = channels;
    data.resize(size_t(width) * height * channels);
    return data.data();
  });
  return data;
}

}  // namespace

Rgb8Image read_rgb8(const std::string& path) {
  int w, h, c;
  auto raw = read_image<uint8_t>(path, detail::PixelType::u8, &w, &h, &c);
  Rgb8Image img;
  img.width = w;
  img.height = h;
  img.pixels.resize(size_t(w) * h * 3);
  for (size_t i = 0; i < size_t(w) * h; ++i)
    for (int k = 0; k < 3; ++k) img.pixels[3 * i + k] = raw[i * c + (c >= 3 ? k : 0)];
  return img;
}

void write_png(const std::string& path, int w, int h, int channels, const uint8_t* data) {
  write_image(path, w, h, channels, detail::PixelType::u8, data);
}

void write_tiff_float(const std::string& path, int w, int h, int channels, const float* data) {
  write_image(path, w, h, channels, detail::PixelType::f32, data);
}

void write_tiff_uint32(const std::string& path, int w, int h, const uint32_t* data) {
  write_image(path, w, h, 1, detail::PixelType::u32, data);
}

struct ImageWriter::State {
  explicit State(size_t max) : max_queued_bytes(max) {}
  std::mutex mutex;
  std::condition_variable room;  // signalled as each image is done
  size_t queued_bytes = 0, queued_images = 0;
  const size_t max_queued_bytes;
  std::exception_ptr error;  // the first failure finish() has not reported
  detail::Worker worker;     // last: destroyed (joined) first
};

ImageWriter::ImageWriter(size_t max_queued_bytes) : state_(std::make_unique<State>(max_queued_bytes)) {}

ImageWriter::~ImageWriter() {
  try {
    finish();
  } catch (...) {
  }
}

void ImageWriter::png(std::string path, int width, int height, int channels, std::vector<uint8_t> pixels) {
  State& s = *state_;
  const size_t bytes = pixels.size();
  {
    std::unique_lock<std::mutex> lock(s.mutex);
    // One image always fits, however large, so a big one cannot wait forever.
    s.room.wait(lock, [&] { return s.queued_images == 0 || s.queued_bytes + bytes <= s.max_queued_bytes; });
    s.queued_bytes += bytes;
    ++s.queued_images;
  }
  // The future is not kept: a failure is reported through finish().
  s.worker.submit([&s, bytes, path = std::move(path), width, height, channels, pixels = std::move(pixels)]() mutable {
    std::exception_ptr failure;
    try {
      write_png(path, width, height, channels, pixels.data());
    } catch (...) {
      failure = std::current_exception();
    }
    pixels = {};
    std::lock_guard<std::mutex> lock(s.mutex);
    if (failure && !s.error) s.error = failure;
    s.queued_bytes -= bytes;
    --s.queued_images;
    s.room.notify_all();
  });
}

void ImageWriter::finish() {
  State& s = *state_;
  std::unique_lock<std::mutex> lock(s.mutex);
  s.room.wait(lock, [&] { return s.queued_images == 0; });
  if (s.error) std::rethrow_exception(std::exchange(s.error, nullptr));
}

std::vector<uint32_t> read_tiff_uint32(const std::string& path, int* w, int* h) {
  int c;
  auto v = read_image<uint32_t>(path, detail::PixelType::u32, w, h, &c);
  if (c != 1) throw std::runtime_error(path + ": expected a one-channel ID image");
  return v;
}

}  // namespace perclod
