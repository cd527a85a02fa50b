// perclod/image_io.h - image files through OpenImageIO. Every image the project
// writes has row 0 at the top. Writes go through write_atomic (perclod/outputs.h),
// so an interrupted run never leaves a half-written image behind.
#pragma once

#include <cstdint>
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

}  // namespace perclod
