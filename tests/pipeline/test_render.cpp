// Renderer: size, orientation, background, ID coverage, offset invariance.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <sstream>

#include "perclod/load.h"
#include "perclod/render.h"
#include "perclod/views.h"
#include "test_util.h"

using namespace perclod;

namespace {

// Appends an axis-aligned quad in the plane z = z0 (normal +z) to a scene as its own component.
void add_quad(Scene& s, float x0, float y0, float x1, float y1, float z0) {
  uint32_t base = uint32_t(s.vertex_count());
  s.positions.insert(s.positions.end(), {x0, y0, z0, x1, y0, z0, x1, y1, z0, x0, y1, z0});
  s.indices.insert(s.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  uint32_t comp = uint32_t(s.component_names.size());
  s.component_names.push_back("quad" + std::to_string(comp));
  s.component.insert(s.component.end(), {comp, comp});
  s.material.insert(s.material.end(), {0, 0});
  if (s.materials.empty()) s.materials.push_back({"grey", {0.6f, 0.6f, 0.6f}, true});
}

Renderer& shared_renderer() {
  static Renderer r;  // one OSMesa context for the whole test binary
  return r;
}

}  // namespace

TEST(Render, SizeBackgroundAndOrientation) {
  // A wall and, in front of it, a marker quad at its top-left corner.
  Scene s;
  add_quad(s, -4, -3, 4, 3, 0);
  add_quad(s, -4, 2, -3, 3, 0.1f);
  Camera c = look_at({0, 0, 20}, {0, 0, 0}, {0, 1, 0}, 0.5, 321, 203, 1, 100);  // odd sizes
  Renderer& r = shared_renderer();
  r.set_scene(s);
  RenderOutput o = r.render(c);
  ASSERT_EQ(o.width, 321);
  ASSERT_EQ(o.height, 203);
  ASSERT_EQ(o.rgb.size(), 321u * 203u * 3u);
  ASSERT_EQ(o.ids.size(), 321u * 203u);
  // Background: corners are white with ID 0.
  for (size_t i : {size_t(0), size_t(320), size_t(202 * 321), size_t(203 * 321 - 1)}) {
    EXPECT_EQ(o.ids[i], 0u);
    EXPECT_EQ(o.rgb[3 * i], 255);
    EXPECT_EQ(o.rgb[3 * i + 2], 255);
  }
  // The marker's centre (-3.5, 2.5) projects to the upper-left: its pixel shows triangle 2 or 3.
  double px, py, depth;
  ASSERT_TRUE(c.project({-3.5, 2.5, 0.1}, px, py, depth));
  EXPECT_LT(px, 321 / 2);
  EXPECT_LT(py, 203 / 2);
  uint32_t id = o.ids[size_t(py) * 321 + size_t(px)];
  EXPECT_TRUE(id == 3 || id == 4) << id;
  // The mirrored spot (lower right) shows the wall.
  ASSERT_TRUE(c.project({3.5, -2.5, 0}, px, py, depth));
  id = o.ids[size_t(py) * 321 + size_t(px)];
  EXPECT_TRUE(id == 1 || id == 2) << id;
  // Shading: the lit wall is neither black nor background.
  size_t centre = size_t(101) * 321 + 160;
  EXPECT_GT(o.rgb[3 * centre], 20);
  EXPECT_LT(o.rgb[3 * centre], 255);
}

TEST(Render, IdBufferCoversExactlyThePixelCentresInsideTheQuad) {
  // The quad's projection is an axis-aligned rectangle; its edges are placed
  // at fractional pixel positions away from any pixel centre.
  Camera c = look_at({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 0.7, 160, 120, 1, 50);
  auto unproject_x = [&](double px) { return (2 * px / c.width - 1) * c.tan_half_y() * c.aspect() * 10; };
  auto unproject_y = [&](double py) { return (1 - 2 * py / c.height) * c.tan_half_y() * 10; };
  double x0 = 20.3, x1 = 97.8, y0 = 11.2, y1 = 88.7;  // pixel coordinates
  Scene s;
  add_quad(s, float(unproject_x(x0)), float(unproject_y(y1)), float(unproject_x(x1)), float(unproject_y(y0)), 0);
  Renderer& r = shared_renderer();
  r.set_scene(s);
  RenderOutput o = r.render(c);
  size_t mismatches = 0, inside = 0;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      bool expect = x + 0.5 > x0 && x + 0.5 < x1 && y + 0.5 > y0 && y + 0.5 < y1;
      inside += expect;
      mismatches += expect != (o.ids[size_t(y) * c.width + x] != 0);
    }
  EXPECT_EQ(inside, size_t(78 * 78));  // centres x + 0.5 in (20.3, 97.8): x = 20..97; y = 11..88
  EXPECT_EQ(mismatches, 0u);
}

TEST(Render, DepthIsEyeDistance) {
  Scene s;
  add_quad(s, -5, -5, 5, 5, 0);
  Camera c = look_at({0, 0, 12.5}, {0, 0, 0}, {0, 1, 0}, 0.5, 64, 48, 1, 40);
  Renderer& r = shared_renderer();
  r.set_scene(s);
  RenderOptions opt;
  opt.want_depth = true;
  RenderOutput o = r.render(c, opt);
  EXPECT_NEAR(o.depth[24 * 64 + 32], 12.5, 1e-3);
}

TEST(Render, TriangleColoursOverrideMaterials) {
  Scene s;
  add_quad(s, -5, -5, 5, 5, 0);
  Camera c = look_at({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 0.5, 32, 32, 1, 40);
  Renderer& r = shared_renderer();
  r.set_scene(s);
  RenderOptions opt;
  opt.triangle_colors = {0, 1, 0, 0, 1, 0};  // both triangles green
  opt.ambient = 1.0;                       // unshaded: exact colour
  RenderOutput o = r.render(c, opt);
  size_t i = 16 * 32 + 16;
  EXPECT_EQ(o.rgb[3 * i], 0);
  EXPECT_EQ(o.rgb[3 * i + 1], 255);
  EXPECT_EQ(o.rgb[3 * i + 2], 0);
  opt.triangle_colors = {1, 0};
  EXPECT_THROW(r.render(c, opt), RenderError);
}

TEST(Render, UtmOffsetRendersTheSameImageToThePixel) {
  // The real building, once as shipped and once with a UTM offset added in the file's text.
  std::ifstream in(PERCLOD_SOURCE_DIR "/data/ingolstadt/bldg_4018215.obj");
  std::ostringstream shifted;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("v ", 0) == 0) {
      std::istringstream ss(line.substr(2));
      std::string x, y, z;
      ss >> x >> y >> z;
      // Add the offset to the integer part, as text: exact decimal addition.
      // (The model has no negative coordinates; the test checks that.)
      auto add = [](const std::string& v, long off) {
        EXPECT_NE(v[0], '-');
        size_t dot = v.find('.');
        std::string frac = dot == std::string::npos ? "" : v.substr(dot);
        return std::to_string(std::stol(v.substr(0, dot)) + off) + frac;
      };
      shifted << "v " << add(x, 678000) << " " << add(y, 5403500) << " " << add(z, 400) << "\n";
    } else {
      shifted << line << "\n";
    }
  }
  test::TempDir dir("utm");
  auto utm_path = dir.file("utm.obj", shifted.str());
  Scene a = load_scene(PERCLOD_SOURCE_DIR "/data/ingolstadt/bldg_4018215.obj");
  Scene b = load_scene(utm_path);
  EXPECT_NEAR(b.offset[0] - a.offset[0], 678000.0, 1e-6);
  EXPECT_NEAR(b.offset[1] - a.offset[1], 5403500.0, 1e-6);
  DisplayProfile d;
  Renderer& r = shared_renderer();
  for (const char* f : {"-y", "+x"}) {
    Camera ca = facade_camera(scene_bounds(a), UpAxis::Z, f, 56, d);
    Camera cb = facade_camera(scene_bounds(b), UpAxis::Z, f, 56, d);
    r.set_scene(a);
    RenderOutput oa = r.render(ca);
    r.set_scene(b);
    RenderOutput ob = r.render(cb);
    size_t covered = 0;
    for (uint32_t id : oa.ids) covered += id != 0;
    EXPECT_GT(covered, 10000u);
    EXPECT_EQ(oa.rgb, ob.rgb) << "facade " << f;
    EXPECT_EQ(oa.ids, ob.ids) << "facade " << f;
  }
}

// Culling skips whole chunks of triangles outside the view and draws the
// rest in their order: a view of part of a scene of many chunks, with
// coplanar copies in different chunks (depth ties, first drawn wins) and
// quads across the image border, gives the same colours, IDs and depth as
// one draw of everything, while fewer triangles are drawn.
TEST(Render, CullingChangesNoPixel) {
  Scene s;
  // 80 x 40 quads of 0.25 m (6,400 triangles, 4 chunks of 2,048), then a
  // coplanar copy of a band of them (later chunk, higher index: must lose).
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 80; ++i) add_quad(s, 0.25f * i, 0.25f * j, 0.25f * i + 0.24f, 0.25f * j + 0.24f, 0.0f);
  for (int j = 10; j < 14; ++j)
    for (int i = 0; i < 80; ++i) add_quad(s, 0.25f * i, 0.25f * j, 0.25f * i + 0.24f, 0.25f * j + 0.24f, 0.0f);
  s.materials[0].color = {0.6f, 0.6f, 0.6f};
  Renderer& r = shared_renderer();
  r.set_scene(s);
  size_t views = 0;
  // Chunks are bands of about 3.2 m in y (the copies' chunk also spans
  // y 2.5-3.5); each view sees a few metres of the 20 m x 10 m field. The
  // last sees neither the first chunk nor the copies: its draw starts at a
  // later chunk, so the IDs check the restored triangle index.
  for (auto [cx, cy] : {std::pair{2.0, 3.0}, {10.0, 3.0}, {17.5, 8.5}}) {
    const Camera cam = look_at({cx, cy, 4.0}, {cx, cy, 0.0}, {0, 1, 0}, 0.9, 160, 120, 0.5, 50);
    RenderOptions all, culled;
    all.cull = false;
    all.want_depth = culled.want_depth = true;
    all.color_by = culled.color_by = ColorBy::Component;
    const RenderOutput a = r.render(cam, all), b = r.render(cam, culled);
    EXPECT_EQ(a.drawn_triangles, s.triangle_count());
    EXPECT_LT(b.drawn_triangles, s.triangle_count()) << "camera at x " << cx << ", y " << cy;
    EXPECT_GT(b.drawn_triangles, 0u);
    EXPECT_EQ(a.rgb, b.rgb) << "camera at x " << cx << ", y " << cy;
    EXPECT_EQ(a.ids, b.ids) << "camera at x " << cx << ", y " << cy;
    EXPECT_EQ(a.depth, b.depth) << "camera at x " << cx << ", y " << cy;
    size_t covered = 0, copies = 0;
    for (uint32_t id : b.ids) {
      covered += id != 0;
      copies += id > 6400;
    }
    EXPECT_GT(covered, size_t(160 * 120 / 2));
    EXPECT_EQ(copies, 0u) << "a coplanar copy drawn later must not win a depth tie";
    ++views;
  }
  EXPECT_EQ(views, 3u);
  // Seen along the field from its -y end, with the far plane 3 m into it:
  // the chunks beyond are skipped, the nearer ones drawn as before; with the
  // near plane 6 m away, the first chunk is skipped.
  for (auto [znear, zfar] : {std::pair{0.5, 5.0}, {6.0, 40.0}}) {
    const Camera cam = look_at({10.0, -2.0, 1.0}, {10.0, 5.0, 0.0}, {0, 0, 1}, 0.9, 160, 120, znear, zfar);
    RenderOptions all, culled;
    all.cull = false;
    all.want_depth = culled.want_depth = true;
    all.color_by = culled.color_by = ColorBy::Component;
    const RenderOutput a = r.render(cam, all), b = r.render(cam, culled);
    EXPECT_LT(b.drawn_triangles, s.triangle_count()) << "near " << znear;
    EXPECT_GT(b.drawn_triangles, 0u);
    EXPECT_EQ(a.rgb, b.rgb) << "near " << znear;
    EXPECT_EQ(a.ids, b.ids) << "near " << znear;
    EXPECT_EQ(a.depth, b.depth) << "near " << znear;
    EXPECT_GT(std::count_if(b.ids.begin(), b.ids.end(), [](uint32_t id) { return id != 0; }), 1000);
  }
}

// A part of the frame holds exactly the whole frame's pixels there (same
// projection, the draw scissored), rows top first; a part that is not in
// the frame is refused.
TEST(Render, APartOfTheFrameIsTheWholeFramesPixels) {
  Scene s;
  for (int j = 0; j < 12; ++j)
    for (int i = 0; i < 20; ++i) add_quad(s, 0.5f * i, 0.5f * j, 0.5f * i + 0.43f, 0.5f * j + 0.41f, 0.05f * (i % 3));
  Renderer& r = shared_renderer();
  r.set_scene(s);
  const Camera cam = look_at({4.0, 1.0, 9.0}, {5.0, 3.0, 0.0}, {0, 1, 0}, 0.7, 211, 163, 0.5, 50);
  RenderOptions whole;
  whole.want_depth = true;
  whole.color_by = ColorBy::Component;
  const RenderOutput a = r.render(cam, whole);
  for (auto [x, y, w, h] : {std::array{37, 21, 101, 77}, {0, 0, 211, 1}, {210, 100, 1, 63}, {64, 32, 147, 131}}) {
    RenderOptions part = whole;
    part.part_x = x, part.part_y = y, part.part_w = w, part.part_h = h;
    const RenderOutput b = r.render(cam, part);
    ASSERT_EQ(b.width, w);
    ASSERT_EQ(b.height, h);
    size_t differ = 0, covered = 0;
    for (int yy = 0; yy < h; ++yy)
      for (int xx = 0; xx < w; ++xx) {
        const size_t i = size_t(yy) * w + xx, j = size_t(y + yy) * cam.width + (x + xx);
        covered += b.ids[i] != 0;
        differ += b.ids[i] != a.ids[j] || b.depth[i] != a.depth[j] || b.rgb[3 * i] != a.rgb[3 * j] ||
                  b.rgb[3 * i + 1] != a.rgb[3 * j + 1] || b.rgb[3 * i + 2] != a.rgb[3 * j + 2];
      }
    EXPECT_EQ(differ, 0u) << w << "x" << h << " at (" << x << ", " << y << ")";
    if (w > 100 && h > 50) {
      EXPECT_GT(covered, size_t(w * h / 4));
    }
  }
  // A whole render after a part draws the whole frame again.
  EXPECT_EQ(r.render(cam, whole).ids, a.ids);
  for (auto [x, y, w, h] : {std::array{-1, 0, 10, 10}, {200, 0, 12, 10}, {0, 160, 10, 4}, {5, 5, 4, 0}, {5, 5, -3, 2}}) {
    RenderOptions part;
    part.part_x = x, part.part_y = y, part.part_w = w, part.part_h = h;
    EXPECT_THROW(r.render(cam, part), RenderError) << w << "x" << h << " at (" << x << ", " << y << ")";
  }
}

// A renderer keeps its framebuffer while a frame fits in it and draws in its
// corner: frames drawn after larger ones (and a larger one after them) are
// those a new renderer draws, pixel for pixel.
TEST(Render, FramesOfManySizesDrawAsOnAFreshRenderer) {
  Scene s;
  for (int j = 0; j < 12; ++j)
    for (int i = 0; i < 20; ++i) add_quad(s, 0.5f * i, 0.5f * j, 0.5f * i + 0.43f, 0.5f * j + 0.41f, 0.05f * (i % 3));
  RenderOptions opt;
  opt.want_depth = true;
  std::vector<Camera> cams;
  for (auto [w, h] : {std::array{400, 300}, {211, 163}, {150, 290}, {97, 61}, {401, 299}, {64, 64}, {500, 40}})
    cams.push_back(look_at({4.0, 1.0, 9.0}, {5.0, 3.0, 0.0}, {0, 1, 0}, 0.7, w, h, 0.5, 50));
  Renderer kept;
  kept.set_scene(s);
  for (const Camera& cam : cams) {
    Renderer fresh;
    fresh.set_scene(s);
    const RenderOutput a = kept.render(cam, opt), b = fresh.render(cam, opt);
    size_t covered = 0;
    for (uint32_t id : a.ids) covered += id != 0;
    EXPECT_GT(covered, a.ids.size() / 20) << cam.width << "x" << cam.height;
    EXPECT_EQ(a.ids, b.ids) << cam.width << "x" << cam.height;
    EXPECT_EQ(a.rgb, b.rgb) << cam.width << "x" << cam.height;
    EXPECT_EQ(a.depth, b.depth) << cam.width << "x" << cam.height;
  }
}

// The renderer keeps its own copies: a scene without component or material
// arrays (Scene's contract: one component, the default material) draws, and
// the scene may be destroyed between set_scene and render.
TEST(Render, DrawsASceneWithoutIdArraysAfterTheSceneIsGone) {
  Camera cam = look_at({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 0.8, 64, 48, 1, 100);
  Renderer& r = shared_renderer();
  {
    Scene s;
    add_quad(s, -1, -1, 1, 1, 0);
    s.component.clear();
    s.material.clear();
    r.set_scene(s);
  }
  RenderOutput out = r.render(cam);
  const size_t centre = size_t(24) * 64 + 32;
  EXPECT_TRUE(out.ids[centre] == 1u || out.ids[centre] == 2u) << out.ids[centre];
  EXPECT_EQ(out.ids[0], 0u);  // a corner shows the background
  RenderOptions by_component;
  by_component.color_by = ColorBy::Component;
  RenderOutput c = r.render(cam, by_component);
  EXPECT_NE(c.rgb[3 * centre], 255) << "the quad is drawn in its component's colour, not the white background";
  EXPECT_EQ(c.rgb[0], 255);
}

TEST(Render, RefusesASceneThatBreaksTheContract) {
  Scene s;
  add_quad(s, -1, -1, 1, 1, 0);
  s.material[1] = 5;
  EXPECT_THROW(shared_renderer().set_scene(s), std::invalid_argument);
}


// Marking images are coloured from a labelling render's ID buffer instead of
// a second draw: the colours match that draw up to rounding.
TEST(Render, ShadeIdsMatchesARenderInTheSameColours) {
  const Scene s = load_scene(PERCLOD_SOURCE_DIR "/data/ingolstadt/bldg_4018215.obj");
  const Camera c = view_camera(scene_bounds(s), UpAxis::Z, "az45el30", 56, DisplayProfile{});
  Renderer& r = shared_renderer();
  r.set_scene(s);
  const RenderOutput plain = r.render(c);
  RenderOptions opt;
  opt.triangle_colors.resize(3 * s.triangle_count());
  for (size_t t = 0; t < s.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) opt.triangle_colors[3 * t + k] = float((t * 37 + size_t(k) * 101) % 256) / 255.f;
  opt.want_ids = false;
  const RenderOutput drawn = r.render(c, opt);
  const std::vector<uint8_t> shaded = shade_ids(s, c, plain.ids, opt.triangle_colors, opt);
  ASSERT_EQ(shaded.size(), drawn.rgb.size());
  size_t covered = 0, off = 0, far = 0;
  for (size_t i = 0; i < plain.ids.size(); ++i) {
    covered += plain.ids[i] != 0;
    int d = 0;
    for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(int(shaded[3 * i + k]) - int(drawn.rgb[3 * i + k])));
    off += d > 0;
    far += d > 2;
  }
  EXPECT_GT(covered, 10000u);
  EXPECT_LT(double(off) / double(covered), 0.005);  // rounding of the normal: 0.16% of the drawn pixels
  EXPECT_EQ(far, 0u);
  EXPECT_THROW(shade_ids(s, c, std::vector<uint32_t>(7), opt.triangle_colors), RenderError);
  EXPECT_THROW(shade_ids(s, c, plain.ids, {1.f, 0.f}), RenderError);
}
