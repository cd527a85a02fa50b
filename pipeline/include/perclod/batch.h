// perclod/batch.h - orchestration: views x distances, files named as the README says.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "perclod/display.h"
#include "perclod/render.h"
#include "perclod/views.h"

namespace perclod {

struct ViewFiles {
  std::string facade;
  double distance = 0;
  std::string color, ids, depth;  // paths written ("" = not requested)
  size_t covered_pixels = 0;      // pixels showing geometry
  double render_seconds = 0;
};

struct RenderViewsJob {
  std::string out_dir = "out";
  std::string stem;                 // file name prefix (the model's stem)
  UpAxis up = UpAxis::Y;
  std::vector<std::string> facades;
  std::vector<double> distances;
  DisplayProfile display;
  bool write_ids = false, write_depth = false;
  ColorBy color_by = ColorBy::Material;
};

// <out>/<stem>_<facade>_<distance>m.png, plus _ids.tif (uint32, triangle index
// + 1) and _depth.tif (float eye depth, metres) on request. `progress` (may be
// empty) is called after each view.
std::vector<ViewFiles> render_views(Renderer& renderer, const Scene& scene, const RenderViewsJob& job,
                                    const std::function<void(const ViewFiles&, size_t done, size_t total)>& progress);

// <out>/<stem>_<facade>_<d>m (the caller adds a suffix and extension).
std::string view_file_base(const std::string& out_dir, const std::string& stem, const std::string& facade,
                           double distance);
// <out>/<stem>_<what>_<d>m<ext>, e.g. out/bldg_labels_56m.txt.
std::string distance_file(const std::string& out_dir, const std::string& stem, const std::string& what,
                          double distance, const std::string& ext);

}  // namespace perclod
