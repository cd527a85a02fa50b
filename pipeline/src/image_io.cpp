// Image files through OpenImageIO; writes are atomic (perclod/outputs.h).
#include "perclod/image_io.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <condition_variable>
#include <exception>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <utility>

#include "perclod/outputs.h"
#include "worker.h"

namespace perclod {
namespace {

// Largest image perclod reads: renders are a few thousand pixels wide.
constexpr int kMaxImageSide = 32768;
constexpr long long kMaxImagePixels = 1LL << 28;
constexpr int kPngLevel = 2;
constexpr int kPngFilterUp = 0x20;  // libpng's PNG_FILTER_UP

std::runtime_error io_error(const std::string& path, const std::string& what) {
  return std::runtime_error(path + ": " + what);
}

// Encodes into memory and writes the bytes with write_bytes_atomic: OIIO's
// PNG writer does not report a failed write or close (a full disk would leave
// a truncated PNG under its final name and report success).
void write_image(const std::string& path, int w, int h, int channels, OIIO::TypeDesc type,
                 const void* data) {
  if (w <= 0 || h <= 0 || channels < 1 || channels > 4) throw io_error(path, "bad image size");
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput mem(bytes);
  auto out = OIIO::ImageOutput::create(path, &mem);
  if (!out) throw io_error(path, "no image writer for this extension");
  if (!out->supports("ioproxy")) throw io_error(path, "the image writer cannot write to memory");
  OIIO::ImageSpec spec(w, h, channels, type);
  if (std::string(out->format_name()) == "png") {
    // Every row filtered with "up" at zlib level 2: on 1280x1024 renders and
    // debug images 3-4x faster to encode than libpng's default (adaptive
    // filters, level 6), for files 0-60% larger (a run writes hundreds).
    spec.attribute("png:compressionLevel", kPngLevel);
    spec.attribute("png:filter", kPngFilterUp);
  }
  if (!out->set_ioproxy(&mem) || !out->open(path, spec) || !out->write_image(type, data) || !out->close())
    throw io_error(path, "cannot encode image: " + out->geterror());
  out.reset();
  write_bytes_atomic(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

template <class T>
std::vector<T> read_image(const std::string& path, OIIO::TypeDesc type, int* w, int* h, int* c) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw io_error(path, "cannot read image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  // The header's size is untrusted: bound it before allocating (a 68-byte PNG
  // declaring 60000x60000 asked for 2 x 10.8 GB).
  const double pixels = double(spec.width) * spec.height;
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels < 1 || spec.nchannels > 16 || spec.depth > 1)
    throw io_error(path, "unsupported image layout (" + std::to_string(spec.width) + "x" +
                             std::to_string(spec.height) + ", " + std::to_string(spec.nchannels) + " channels)");
  if (spec.width > kMaxImageSide || spec.height > kMaxImageSide || pixels > double(kMaxImagePixels))
    throw io_error(path, "image size " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                             " is beyond perclod's limit (" + std::to_string(kMaxImageSide) + " per side, " +
                             std::to_string(kMaxImagePixels) + " pixels): corrupt or not a perclod image");
  std::error_code ec;
  const auto file_bytes = std::filesystem::file_size(path, ec);
  // Deflate (PNG) expands at most ~1032:1; allow some slack for the format's own structures.
  if (!ec && std::string(in->format_name()) == "png" &&
      pixels * spec.nchannels * spec.format.size() > 1100.0 * double(file_bytes) + 65536)
    throw io_error(path, "PNG header declares " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                             " pixels, more than its " + std::to_string(file_bytes) +
                             " bytes can hold (truncated or corrupt)");
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
  auto v = read_image<uint32_t>(path, OIIO::TypeDesc::UINT32, w, h, &c);
  if (c != 1) throw io_error(path, "expected a one-channel ID image");
  return v;
}

}  // namespace perclod
