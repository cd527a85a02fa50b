// libperclod_oiio.so: perclod's image encoding and decoding through
// OpenImageIO, loaded on first use by pipeline/io/src/image_io.cpp (see
// image_codec.h for why it is a module of its own).
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "image_codec.h"

namespace {

using perclod::detail::ImageCodec;
using perclod::detail::PixelType;

// Largest image perclod reads: renders are a few thousand pixels wide.
constexpr int kMaxImageSide = 32768;
constexpr long long kMaxImagePixels = 1LL << 28;
constexpr int kPngLevel = 2;
constexpr int kPngFilterUp = 0x20;  // libpng's PNG_FILTER_UP

std::runtime_error io_error(const std::string& path, const std::string& what) {
  return std::runtime_error(path + ": " + what);
}

OIIO::TypeDesc type_of(PixelType t) {
  switch (t) {
    case PixelType::u8: return OIIO::TypeDesc::UINT8;
    case PixelType::u32: return OIIO::TypeDesc::UINT32;
    case PixelType::f32: return OIIO::TypeDesc::FLOAT;
  }
  throw std::logic_error("image_oiio: unknown pixel type");
}

// Encodes into memory: the caller writes the bytes atomically, because OIIO's
// PNG writer does not report a failed write or close (a full disk would leave
// a truncated PNG under its final name and report success).
std::vector<unsigned char> encode(const std::string& path, int w, int h, int channels, PixelType pixel_type,
                                  const void* data) {
  if (w <= 0 || h <= 0 || channels < 1 || channels > 4) throw io_error(path, "bad image size");
  const OIIO::TypeDesc type = type_of(pixel_type);
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
  return bytes;
}

void decode(const std::string& path, PixelType pixel_type,
            const std::function<void*(int width, int height, int channels)>& buffer) {
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
  void* data = buffer(spec.width, spec.height, spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, type_of(pixel_type), data))
    throw io_error(path, "cannot decode image: " + in->geterror());
}

constexpr ImageCodec kCodec{perclod::detail::kImageCodecAbi, encode, decode};

}  // namespace

extern "C" __attribute__((visibility("default"))) const ImageCodec* perclod_image_codec() { return &kCodec; }
