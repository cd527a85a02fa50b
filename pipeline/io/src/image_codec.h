// The image codec perclod_pipeline loads at run time (private to the
// pipeline). OpenImageIO does perclod's image encoding and decoding, but it
// links some 260 shared libraries (its format plugins' codecs, OpenCV, GDAL,
// FFmpeg...) whose loading took 0.42 s of every process start on the 2-core
// VM. It therefore lives in a module of its own, libperclod_oiio.so
// (pipeline/oiio/), which the first image read or write dlopen()s: a
// process that reads or writes no image (perclod --help, info, simplify,
// most tests) never pays for it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace perclod::detail {

enum class PixelType : int { u8, u32, f32 };

// Raised by the module's `abi` below when either side of this header changes.
constexpr int kImageCodecAbi = 1;

struct ImageCodec {
  int abi;  // kImageCodecAbi of the module's build
  // The file bytes of a width x height image of `channels` interleaved
  // channels of `type`, row 0 at the top, in the format path's extension
  // names (PNG: filter "up", zlib level 2). Throws std::runtime_error naming
  // path.
  std::vector<unsigned char> (*encode)(const std::string& path, int width, int height, int channels,
                                       PixelType type, const void* pixels);
  // Reads path's header, refuses sizes beyond perclod's limits, then decodes
  // into buffer(width, height, channels), which returns room for
  // width * height * channels values of `type`. Throws std::runtime_error
  // naming path.
  void (*decode)(const std::string& path, PixelType type,
                 const std::function<void*(int width, int height, int channels)>& buffer);
};

// The module's one exported symbol, an extern "C" function of this type
// named kImageCodecEntry, returns its table.
using ImageCodecEntry = const ImageCodec* (*)();
inline constexpr const char* kImageCodecEntry = "perclod_image_codec";

// The codec, loading the module on the first call (thread-safe). Throws
// std::runtime_error naming the module file when it cannot be loaded.
const ImageCodec& image_codec();

}  // namespace perclod::detail
