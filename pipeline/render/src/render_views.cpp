// perclod render: every requested view (framed, tiled when needed) at every
// distance, written as images.
#include "perclod/image_io.h"
#include "perclod/render_views.h"

namespace perclod {

std::vector<ViewFiles> render_views(const Scene& scene, const RenderViewsJob& job,
                                    const std::function<void(const ViewFiles&, size_t, size_t)>& progress) {
  OutputDirectoryLock lock(job.out.dir);
  Bounds b = scene_bounds(scene);
  std::vector<ViewFiles> done;
  // Every view framed at every distance first: one that cannot be framed
  // fails before any rendering.
  std::vector<std::pair<double, ViewTile>> tiles;
  for (double d : job.distances)
    for (const auto& v : job.views)
      for (ViewTile& t : frame_view(b, job.up, v, d, job.display)) tiles.emplace_back(d, std::move(t));
  const size_t total = tiles.size();
  Renderer renderer;
  renderer.set_scene(scene);
  for (const auto& [d, tile] : tiles) {
    const std::string& f = tile.name;
    const Camera& cam = tile.camera;
    RenderOptions opt;
    opt.color_by = job.color_by;
    opt.want_ids = true;
    opt.want_depth = job.write_depth;
    RenderOutput r = renderer.render(cam, opt);
    ViewFiles v;
    v.view = f;
    v.distance = d;
    v.render_seconds = r.seconds;
    for (uint32_t id : r.ids) v.covered_pixels += id != 0;
    v.drawn_triangles = r.drawn_triangles;
    v.color = job.out.view(f, d, ".png");
    write_png(v.color, r.width, r.height, 3, r.rgb.data());
    if (job.write_ids) {
      v.ids = job.out.view(f, d, "_ids.tif");
      write_tiff_uint32(v.ids, r.width, r.height, r.ids.data());
    }
    if (job.write_depth) {
      v.depth = job.out.view(f, d, "_depth.tif");
      write_tiff_float(v.depth, r.width, r.height, 1, r.depth.data());
    }
    done.push_back(v);
    if (progress) progress(v, done.size(), total);
  }
  return done;
}

}  // namespace perclod
