// perclod/image_io.h - image files through OpenImageIO. Every image the project
// writes has row 0 at the top. Writes go through write_atomic (perclod/outputs.h),
// so an interrupted run never leaves a half-written image behind.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace perclod {

struct Rgb8Image {
  int width = 0, height = 0;
  std::vector<uint8_t> pixels;  // RGB, 3 bytes per pixel, row 0 top
};

// Reads any format OpenImageIO knows; grey is expanded to RGB, alpha dropped.
// Throws std::runtime_error naming the file on failure.
Rgb8Image read_rgb8(const std::string& path);

// 8-bit PNG with 1 (grey), 3 (RGB) or 4 channels.
void write_png(const std::string& path, int width, int height, int channels, const uint8_t* data);
// Lossless 32-bit float TIFF (1..4 channels).
void write_tiff_float(const std::string& path, int width, int height, int channels, const float* data);
// Lossless 32-bit unsigned TIFF, one channel (triangle-ID buffers).
void write_tiff_uint32(const std::string& path, int width, int height, const uint32_t* data);
std::vector<uint32_t> read_tiff_uint32(const std::string& path, int* width, int* height);

// Encodes and writes PNGs (write_png) on a thread of its own, so a run's
// debug images are compressed while the next view renders and traces. The
// files are the bytes write_png writes. png() blocks while more than
// `max_queued_bytes` of pixels wait; finish() waits for every queued image
// and rethrows the first failure (later images are still written). The
// destructor waits too and drops a failure finish() did not report.
class ImageWriter {
 public:
  explicit ImageWriter(size_t max_queued_bytes = size_t(64) << 20);
  ~ImageWriter();
  ImageWriter(const ImageWriter&) = delete;
  ImageWriter& operator=(const ImageWriter&) = delete;

  void png(std::string path, int width, int height, int channels, std::vector<uint8_t> pixels);
  void finish();

 private:
  struct State;  // a detail::Worker and the queue's byte count (image_io.cpp)
  std::unique_ptr<State> state_;
};

// Writes through `writer` when there is one, else at once.
inline void write_png_via(ImageWriter* writer, const std::string& path, int width, int height, int channels,
                          std::vector<uint8_t> pixels) {
  if (writer) writer->png(path, width, height, channels, std::move(pixels));
  else write_png(path, width, height, channels, pixels.data());
}

}  // namespace perclod
