// perclod/render.h - the offscreen OSMesa renderer.
//
// One draw gives a shaded colour image, a triangle-ID buffer (triangle index
// + 1, 0 for background) and depth. A 3.3 core context is requested (Mesa
// 22 gives 4.5 core, which glClipControl needs) and drawn by llvmpipe, FBO with
// RGBA8 + R32UI + DEPTH_COMPONENT32F, reversed-Z (glClipControl ZERO_TO_ONE,
// GL_GREATER, clear 0), no MSAA, no dithering. The camera is perclod::Camera,
// the same one the ray caster uses; rows are flipped so row 0 is the top.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

#include "perclod/camera.h"
#include "perclod/scene.h"

namespace perclod {

struct RenderError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class ColorBy { Material, Component };

struct RenderOptions {
  ColorBy color_by = ColorBy::Material;  // materials without a colour fall back to the component's
  std::array<uint8_t, 3> background{255, 255, 255};
  double ambient = 0.35;                  // plus a directional key light from above the eye
  bool want_ids = true;
  bool want_depth = false;
  // When non-empty (3 floats per triangle, 0..1): flat per-triangle colours
  // instead of materials, e.g. marking colours. Shading still applies.
  std::vector<float> triangle_colors;
  // Skip chunks of triangles outside the view (render.cpp); the output is the
  // same either way. false draws everything in one call (tests compare).
  bool cull = true;
  // Only part of the frame: pixels [part_x, part_x + part_w) x [part_y,
  // part_y + part_h) of the camera's image (row 0 top) are drawn (the draw
  // is scissored to them) and read back; the output is that part, part_w x
  // part_h. Each of its pixels is the one a render of the whole frame
  // draws there: the projection is the whole frame's, where a camera
  // cropped to the part (perclod::cropped) rounds differently at edges.
  // part_w = 0: the whole frame.
  int part_x = 0, part_y = 0, part_w = 0, part_h = 0;
};

struct RenderOutput {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;    // 3 per pixel, row 0 top
  std::vector<uint32_t> ids;   // per pixel, triangle index + 1 (0 = background)
  std::vector<float> depth;    // per pixel, eye depth in metres (0 = background)
  double seconds = 0;          // draw + read back
  size_t drawn_triangles = 0;  // sent to OpenGL: all but the chunks culled (RenderOptions::cull)
};

class Renderer {
 public:
  Renderer();  // creates the OSMesa context; throws RenderError if it cannot
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Validates `scene` (perclod::validate) and uploads its geometry and
  // colours; the renderer keeps its own copies, so `scene` may go away after.
  // render() draws the scene given last.
  void set_scene(const Scene& scene);
  RenderOutput render(const Camera& camera, const RenderOptions& options = {});
  // The same into `out`, reusing its buffers: a run renders hundreds of
  // 1280x1024 views, and fresh 14 MB of buffers each time cost page faults.
  void render(const Camera& camera, RenderOutput& out, const RenderOptions& options = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The colours render(camera, {triangle_colors}) would draw, made from an ID
// buffer of `scene` from the same camera (RenderOutput::ids) instead of a
// second draw: each pixel takes its triangle's colour under the renderer's
// flat two-sided lighting (`options`: background, ambient). RGB, row 0 top.
// Equal to the render up to rounding: the shader takes the face normal from
// screen-space derivatives, this from the triangle's corners.
std::vector<uint8_t> shade_ids(const Scene& scene, const Camera& camera, const std::vector<uint32_t>& ids,
                               const std::vector<float>& triangle_colors, const RenderOptions& options = {});

// The per-component fallback colour (deterministic, well separated hues).
std::array<float, 3> component_color(uint32_t component);

}  // namespace perclod
