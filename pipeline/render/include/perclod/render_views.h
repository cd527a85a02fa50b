// perclod/render_views.h - `perclod render`: shaded views of a model with
// their triangle-ID and depth buffers, one file per view, tile and distance.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "perclod/display.h"
#include "perclod/outputs.h"
#include "perclod/render.h"
#include "perclod/views.h"

namespace perclod {

struct ViewFiles {
  std::string view;
  double distance = 0;
  std::string color, ids, depth;  // paths written ("" = not requested)
  size_t covered_pixels = 0;      // pixels showing geometry
  size_t drawn_triangles = 0;     // sent to OpenGL after culling what lies outside the view
  double render_seconds = 0;
};

struct RenderViewsJob {
  OutputNames out;
  UpAxis up = UpAxis::Y;
  std::vector<std::string> views;     // view names (tiled like labelling views)
  std::vector<double> distances;
  DisplayProfile display;
  bool write_ids = false, write_depth = false;
  ColorBy color_by = ColorBy::Material;
};

// out.view(view, d, ".png") per view and tile, plus "_ids.tif" (uint32, triangle index + 1)
// and "_depth.tif" (float eye depth, metres) on request. `progress` (may be
// empty) is called after each view.
std::vector<ViewFiles> render_views(const Scene& scene, const RenderViewsJob& job,
                                    const std::function<void(const ViewFiles&, size_t done, size_t total)>& progress);

}  // namespace perclod
