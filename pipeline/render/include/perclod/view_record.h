// perclod/view_record.h - what a render showed, kept between the stages of a
// job: the original's colours from one view (for judging a LOD later) and a
// labelling render's triangle IDs (for its marking image).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "perclod/camera.h"
#include "perclod/render.h"

namespace perclod {

// What the original looked like from one view, kept to judge a LOD from the
// same view: a labelling view, or a held-out view (record_views). Only the
// rectangle the original draws, widened by kRecordMargin pixels, is kept
// (a building at 427 m covers a few thousand of a view's million pixels);
// outside it the original drew nothing: background, background_rgb. The
// render's colours are kept, not its perception: the judge rebuilds the
// whole render from them and perceives it again, with the same figures to
// the last bit. The colours are packed losslessly (zlib): at 56 m a
// 1M-triangle model is judged from 86 tiles that its records nearly fill,
// 3.9 MB each at 3 bytes a pixel, 22-240 KB packed.
constexpr int kRecordMargin = 16;
struct ViewRecord {
  std::string view;  // view name (with "_t<i>" for a tile)
  Camera camera;
  int x0 = 0, y0 = 0, w = 0, h = 0;       // the kept rectangle of the camera's image
  std::vector<uint8_t> packed_rgb;         // the render's colours, w x h x 3, row 0 top, packed (zlib)
  std::vector<bool> background;            // true where no triangle was drawn (a bit each)
  uint8_t background_rgb[3] = {255, 255, 255};  // the colour of an undrawn pixel
  std::string set = "labelling";           // "labelling" or "held_out"
  // The judge's perceptual floor for this view (measure_floors): how visible
  // moving the original by a quarter pixel is; < 0 until measured.
  double visible_floor = -1;
  double visible_floor_local = -1;  // the same, visible_difference_local (kLocalBlockPx)

  // Index into the kept arrays of image pixel (x, y), or -1 outside them.
  long kept(int x, int y) const {
    return x >= x0 && x < x0 + w && y >= y0 && y < y0 + h ? long(y - y0) * w + (x - x0) : -1;
  }
  bool background_at(int x, int y) const {
    const long k = kept(x, y);
    return k < 0 || background[size_t(k)];
  }
  // The kept rectangle's colours, w x h x 3, unpacked.
  void rgb_into(std::vector<uint8_t>& rgb) const;
  // The whole render, camera.width x camera.height x 3: the kept rectangle
  // over the undrawn colour.
  void render_into(std::vector<uint8_t>& image) const;
};

// A labelling render's triangle IDs, kept to colour its marking image once
// the labels are final (shade_ids).
struct IdBuffer {
  std::string view;  // view name (with "_t<i>" for a tile)
  Camera camera;
  std::vector<uint8_t> packed_ids;  // camera.width x camera.height IDs (triangle + 1, 0 = none), packed (zlib)
  void ids_into(std::vector<uint32_t>& ids) const;
};

// 1 where the render drew no triangle (from its ID buffer).
void background_of(const RenderOutput& img, std::vector<uint8_t>& background);

// A ViewRecord of the original from one view's render (rgb, 3 bytes a
// pixel, and its background mask): the rectangle it draws, widened by
// kRecordMargin and clipped to the image. Without `pixels` its colours are
// not packed (packed_rgb empty, and rgb_into / render_into throw; for a
// caller done with them once the record's rectangle and mask are known).
ViewRecord view_record(const std::string& name, const Camera& camera, const std::vector<uint8_t>& rgb,
                       const std::vector<uint8_t>& background, const std::string& set, bool pixels = true);

}  // namespace perclod
