// What a render showed, kept between a job's stages (perclod/view_record.h):
// the kept rectangle of the original's colours and the labelling renders' IDs,
// packed losslessly.
#include "perclod/view_record.h"

#include <algorithm>

#include "perclod/packing.h"

namespace perclod {
using detail::pack_bytes;
using detail::unpack_bytes;

void background_of(const RenderOutput& img, std::vector<uint8_t>& background) {
  background.resize(img.ids.size());
  for (size_t i = 0; i < img.ids.size(); ++i) background[i] = img.ids[i] == 0;
}

ViewRecord view_record(const std::string& name, const Camera& camera, const std::vector<uint8_t>& rgb,
                       const std::vector<uint8_t>& background, const std::string& set, bool pixels) {
  ViewRecord r;
  r.view = name;
  r.camera = camera;
  r.set = set;
  const int W = camera.width, H = camera.height;
  int x0 = W, y0 = H, x1 = -1, y1 = -1;
  size_t undrawn = background.size();  // some undrawn pixel, for the background's colour
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const size_t i = size_t(y) * size_t(W) + size_t(x);
      if (background[i]) {
        undrawn = i;
        continue;
      }
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = y;
    }
  if (undrawn < background.size()) std::copy_n(&rgb[3 * undrawn], 3, r.background_rgb);
  if (x1 < 0) return r;  // nothing drawn: nothing kept
  r.x0 = std::max(0, x0 - kRecordMargin), r.y0 = std::max(0, y0 - kRecordMargin);
  r.w = std::min(W - 1, x1 + kRecordMargin) - r.x0 + 1, r.h = std::min(H - 1, y1 + kRecordMargin) - r.y0 + 1;
  const size_t n = size_t(r.w) * size_t(r.h);
  thread_local std::vector<uint8_t> kept;  // the rectangle's colours, packed below
  kept.resize(pixels ? 3 * n : 0);
  r.background.resize(n);
  for (int y = 0; y < r.h; ++y) {
    const size_t row = size_t(y + r.y0) * size_t(W) + size_t(r.x0), k = size_t(y) * size_t(r.w);
    if (pixels) std::copy_n(&rgb[3 * row], 3 * size_t(r.w), &kept[3 * k]);
    for (int x = 0; x < r.w; ++x) r.background[k + size_t(x)] = background[row + size_t(x)] != 0;
  }
  if (pixels) r.packed_rgb = pack_bytes(kept.data(), kept.size());
  return r;
}

void ViewRecord::rgb_into(std::vector<uint8_t>& rgb) const {
  rgb.resize(3 * size_t(w) * size_t(h));
  if (!rgb.empty()) unpack_bytes(packed_rgb, rgb.data(), rgb.size());
}

void ViewRecord::render_into(std::vector<uint8_t>& image) const {
  thread_local std::vector<uint8_t> kept;
  rgb_into(kept);
  const size_t W = size_t(camera.width), H = size_t(camera.height);
  image.resize(W * H * 3);
  for (size_t i = 0; i < W * H; ++i) std::copy_n(background_rgb, 3, &image[3 * i]);
  for (int y = 0; y < h; ++y)
    std::copy_n(&kept[3 * size_t(y) * size_t(w)], 3 * size_t(w), &image[3 * ((size_t(y0 + y) * W) + size_t(x0))]);
}

void IdBuffer::ids_into(std::vector<uint32_t>& ids) const {
  ids.resize(size_t(camera.width) * size_t(camera.height));
  if (!ids.empty()) unpack_bytes(packed_ids, ids.data(), ids.size() * sizeof(uint32_t));
}

}  // namespace perclod
