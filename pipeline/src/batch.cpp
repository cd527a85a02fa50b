#include "perclod/batch.h"

#include <sstream>

#include "perclod/image_io.h"

namespace perclod {

std::string distance_file(const std::string& out_dir, const std::string& stem, const std::string& what,
                          double distance, const std::string& ext) {
  std::ostringstream ss;
  ss << out_dir << "/" << stem << "_" << what << "_" << distance << "m" << ext;
  return ss.str();
}

std::string view_file_base(const std::string& out_dir, const std::string& stem, const std::string& facade,
                           double distance) {
  return distance_file(out_dir, stem, facade, distance, "");
}

std::vector<ViewFiles> render_views(Renderer& renderer, const Scene& scene, const RenderViewsJob& job,
                                    const std::function<void(const ViewFiles&, size_t, size_t)>& progress) {
  ensure_directory(job.out_dir);
  renderer.set_scene(scene);
  Bounds b = scene_bounds(scene);
  std::vector<ViewFiles> done;
  size_t total = job.facades.size() * job.distances.size();
  for (double d : job.distances)
    for (const auto& f : job.facades) {
      Camera cam = facade_camera(b, job.up, f, d, job.display);
      RenderOptions opt;
      opt.color_by = job.color_by;
      opt.want_ids = true;
      opt.want_depth = job.write_depth;
      RenderOutput r = renderer.render(cam, opt);
      ViewFiles v;
      v.facade = f;
      v.distance = d;
      v.render_seconds = r.seconds;
      for (uint32_t id : r.ids) v.covered_pixels += id != 0;
      std::string base = view_file_base(job.out_dir, job.stem, f, d);
      v.color = base + ".png";
      write_png(v.color, r.width, r.height, 3, r.rgb.data());
      if (job.write_ids) {
        v.ids = base + "_ids.tif";
        write_tiff_uint32(v.ids, r.width, r.height, r.ids.data());
      }
      if (job.write_depth) {
        v.depth = base + "_depth.tif";
        write_tiff_float(v.depth, r.width, r.height, 1, r.depth.data());
      }
      done.push_back(v);
      if (progress) progress(v, done.size(), total);
    }
  return done;
}

}  // namespace perclod
