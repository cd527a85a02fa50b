// The OSMesa renderer (design notes in perclod/render.h and docs/method.md section 2).
//
// Geometry is drawn indexed from one vertex buffer. Flat shading needs no
// per-vertex normals: the fragment shader takes the face normal from the
// screen-space derivatives of the world position. Per-triangle colours live in
// a buffer texture read with gl_PrimitiveID, which also gives the ID buffer,
// so one draw produces colour, IDs and depth.
//
// Culling: the triangles are cut, in their own order, into chunks of
// kChunkTriangles with a bounding box each. A render skips every chunk whose
// box lies wholly outside one of the view's four side planes (widened by two
// pixels) or wholly nearer than its near plane or beyond its far one, and
// draws the remaining runs of consecutive chunks in order, one
// draw each (`base` restores the triangle index that gl_PrimitiveID restarts).
// A skipped triangle could have drawn no fragment, and the drawn ones keep
// their order, so depth ties resolve as in one draw: the images, IDs and
// depth are the same bit for bit (test Render.CullingChangesNoPixel). It
// pays where a view sees part of the model: the tiles of a near view, and
// the views framed on one building or group of a district.
#include "perclod/render.h"

#include <GL/osmesa.h>
#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

namespace perclod {
namespace {

const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
uniform mat4 view_proj;
out vec3 world;
void main() {
  world = position;
  gl_Position = view_proj * vec4(position, 1.0);
}
)";

// Two-sided lighting: real building models have inconsistent winding.
const char* kFragmentShader = R"(#version 330 core
in vec3 world;
uniform samplerBuffer colors;   // RGB per triangle
uniform uint base;              // gl_PrimitiveID restarts per draw
uniform vec3 light_dir;         // towards the light
uniform vec3 eye;
uniform float ambient;
layout(location = 0) out vec4 color;
layout(location = 1) out uint id;
void main() {
  vec3 n = normalize(cross(dFdx(world), dFdy(world)));
  if (dot(n, eye - world) < 0.0) n = -n;
  float diffuse = max(dot(n, light_dir), 0.0);
  vec3 albedo = texelFetch(colors, gl_PrimitiveID + int(base)).rgb;
  color = vec4(albedo * (ambient + (1.0 - ambient) * diffuse), 1.0);
  id = uint(gl_PrimitiveID) + base + 1u;
}
)";

GLuint compile(GLenum type, const char* src) {
  GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &src, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    throw RenderError(std::string("shader compilation failed: ") + log);
  }
  return s;
}

// Towards the key light: above and to the left of the eye, so facade relief
// casts shading (render() and shade_ids()).
Eigen::Vector3d key_light(const Camera& cam) { return (-cam.forward + 0.8 * cam.up - 0.5 * cam.right).normalized(); }

}  // namespace

std::array<float, 3> component_color(uint32_t c) {
  // Golden-ratio hue walk, moderate saturation: neighbours differ, none is garish.
  double h = std::fmod(0.13 + c * 0.618033988749895, 1.0) * 6.0;
  double s = 0.35, v = 0.85;
  int i = int(h);
  double f = h - i, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  double r[6][3] = {{v, t, p}, {q, v, p}, {p, v, t}, {p, q, v}, {t, p, v}, {v, p, q}};
  return {float(r[i % 6][0]), float(r[i % 6][1]), float(r[i % 6][2])};
}

struct Renderer::Impl {
  OSMesaContext ctx = nullptr;
  std::vector<unsigned char> dummy;  // OSMesaMakeCurrent wants a buffer even when drawing to an FBO
  GLuint program = 0, vao = 0, vbo = 0, ebo = 0, color_buf = 0, color_tex = 0;
  GLuint fbo = 0, rb_color = 0, rb_id = 0, rb_depth = 0;
  int fb_w = 0, fb_h = 0;
  size_t index_count = 0;
  static constexpr size_t kChunkTriangles = 2048;
  std::vector<Bounds> chunk_box;  // the box of each chunk's triangles
  // Copies of what colouring needs, so nothing points into the caller's scene.
  bool has_scene = false;
  size_t triangle_count = 0;
  std::vector<float> material_colors;    // RGB per triangle
  std::vector<float> component_colors;   // RGB per triangle, made on first use
  std::vector<uint32_t> component;       // per triangle (Scene::component_of)
  // Which colours the buffer texture holds: a render in the same colours as
  // the last one uploads nothing (12 MB per render at 1M triangles).
  enum class Colors { None, Material, Component, Custom } uploaded = Colors::None;
  // Read-back scratch, kept between renders.
  std::vector<uint8_t> rgba;
  std::vector<float> z;

  void make_current() {
    if (!OSMesaMakeCurrent(ctx, dummy.data(), GL_UNSIGNED_BYTE, 1, 1))
      throw RenderError("OSMesaMakeCurrent failed");
  }

  // Makes the framebuffer hold a w x h frame in its bottom-left corner (the
  // viewport). A new one has room to grow by an eighth, in llvmpipe's
  // 64-pixel tiles; one that holds the frame and is at most twice the area
  // a new one would have is kept. A building's views from 21 directions are
  // of many sizes, and reallocating three attachments for each cost
  // llvmpipe more than clearing the larger buffer does.
  static int room(int n) { return std::min(16384, (n + n / 8 + 63) / 64 * 64); }
  void fit(int w, int h) {
    if (w <= fb_w && h <= fb_h && double(fb_w) * fb_h <= 2.0 * double(room(w)) * room(h)) return;
    w = room(w);
    h = room(h);
    if (fbo) {
      glDeleteFramebuffers(1, &fbo);
      GLuint rbs[3] = {rb_color, rb_id, rb_depth};
      glDeleteRenderbuffers(3, rbs);
    }
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    auto rb = [&](GLenum fmt, GLenum attach) {
      GLuint r;
      glGenRenderbuffers(1, &r);
      glBindRenderbuffer(GL_RENDERBUFFER, r);
      glRenderbufferStorage(GL_RENDERBUFFER, fmt, w, h);
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, attach, GL_RENDERBUFFER, r);
      return r;
    };
    rb_color = rb(GL_RGBA8, GL_COLOR_ATTACHMENT0);
    rb_id = rb(GL_R32UI, GL_COLOR_ATTACHMENT1);
    rb_depth = rb(GL_DEPTH_COMPONENT32F, GL_DEPTH_ATTACHMENT);
    GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, bufs);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw RenderError("framebuffer incomplete at " + std::to_string(w) + "x" + std::to_string(h));
    fb_w = w;
    fb_h = h;
  }

  void upload_colors(const std::vector<float>& rgb, Colors which) {
    if (which != Colors::Custom && which == uploaded) return;
    uploaded = which;
    glBindBuffer(GL_TEXTURE_BUFFER, color_buf);
    glBufferData(GL_TEXTURE_BUFFER, GLsizeiptr(rgb.size() * sizeof(float)), rgb.data(), GL_DYNAMIC_DRAW);
  }

  // Uploads the colours a render asks for: its own per triangle, the
  // components' (made on first use) or the materials'.
  void select_colors(const RenderOptions& opt) {
    if (!opt.triangle_colors.empty()) {
      if (opt.triangle_colors.size() != 3 * triangle_count)
        throw RenderError("triangle_colors must hold 3 floats per triangle");
      upload_colors(opt.triangle_colors, Colors::Custom);
    } else if (opt.color_by == ColorBy::Component) {
      if (component_colors.empty()) {
        component_colors.resize(3 * triangle_count);
        for (size_t t = 0; t < triangle_count; ++t) {
          auto c = component_color(component[t]);
          for (int k = 0; k < 3; ++k) component_colors[3 * t + k] = c[k];
        }
      }
      upload_colors(component_colors, Colors::Component);
    } else {
      upload_colors(material_colors, Colors::Material);
    }
  }
};

Renderer::Renderer() : impl_(new Impl) {
  const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION, 3, OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
  impl_->ctx = OSMesaCreateContextAttribs(attribs, nullptr);
  if (!impl_->ctx)
    throw RenderError("cannot create an OSMesa OpenGL 3.3 core context (is libosmesa6 installed and "
                      "is GALLIUM_DRIVER/llvmpipe usable?)");
  impl_->dummy.assign(4, 0);
  impl_->make_current();
  auto clip_control = reinterpret_cast<void (*)(GLenum, GLenum)>(OSMesaGetProcAddress("glClipControl"));
  if (!clip_control) throw RenderError("glClipControl is not available: reversed-Z needs OpenGL 4.5");
  clip_control(GL_LOWER_LEFT, GL_ZERO_TO_ONE);

  GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader), fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
  impl_->program = glCreateProgram();
  glAttachShader(impl_->program, vs);
  glAttachShader(impl_->program, fs);
  glLinkProgram(impl_->program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(impl_->program, GL_LINK_STATUS, &ok);
  if (!ok) throw RenderError("shader link failed");
  glGenVertexArrays(1, &impl_->vao);
  glGenBuffers(1, &impl_->vbo);
  glGenBuffers(1, &impl_->ebo);
  glGenBuffers(1, &impl_->color_buf);
  glGenTextures(1, &impl_->color_tex);
  glBindBuffer(GL_TEXTURE_BUFFER, impl_->color_buf);  // a name becomes a buffer only once bound
  glBindTexture(GL_TEXTURE_BUFFER, impl_->color_tex);
  glTexBuffer(GL_TEXTURE_BUFFER, GL_RGB32F, impl_->color_buf);
  glDisable(GL_DITHER);
  glDisable(GL_MULTISAMPLE);
  glDisable(GL_CULL_FACE);  // no culling: back faces are real surfaces in building models
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);  // reversed-Z
  glClearDepth(0.0);
}

Renderer::~Renderer() {
  if (impl_->ctx) OSMesaDestroyContext(impl_->ctx);
}

void Renderer::set_scene(const Scene& s) {
  validate(s);
  impl_->make_current();
  glBindVertexArray(impl_->vao);
  glBindBuffer(GL_ARRAY_BUFFER, impl_->vbo);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(s.positions.size() * sizeof(float)), s.positions.data(), GL_STATIC_DRAW);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, impl_->ebo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(s.indices.size() * sizeof(uint32_t)), s.indices.data(),
               GL_STATIC_DRAW);
  impl_->index_count = s.indices.size();
  const size_t nt = s.triangle_count();
  const size_t chunks = (nt + Impl::kChunkTriangles - 1) / Impl::kChunkTriangles;
  impl_->chunk_box.assign(chunks, Bounds::empty());
  for (size_t t = 0; t < nt; ++t) {
    Bounds& b = impl_->chunk_box[t / Impl::kChunkTriangles];
    for (int c = 0; c < 3; ++c) b.grow(&s.positions[3 * size_t(s.indices[3 * t + c])]);
  }
  impl_->triangle_count = nt;
  impl_->component.resize(nt);
  auto& mc = impl_->material_colors;
  mc.resize(3 * nt);
  for (size_t t = 0; t < nt; ++t) {
    impl_->component[t] = s.component_of(t);
    const Material* m = s.material_of(t);
    auto c = m && m->has_color ? m->color : component_color(impl_->component[t]);
    for (int k = 0; k < 3; ++k) mc[3 * t + k] = c[k];
  }
  impl_->component_colors.clear();
  impl_->uploaded = Impl::Colors::None;
  impl_->has_scene = true;
}

RenderOutput Renderer::render(const Camera& cam, const RenderOptions& opt) {
  RenderOutput out;
  render(cam, out, opt);
  return out;
}

namespace {

// Clears the framebuffer's colour to the background, its IDs to 0 and its
// depth to 0 (reversed-Z far), and sets the viewport to the camera's frame.
void clear_framebuffer(GLuint fbo, const Camera& cam, const std::array<uint8_t, 3>& background) {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glViewport(0, 0, cam.width, cam.height);
  float bg[4] = {background[0] / 255.f, background[1] / 255.f, background[2] / 255.f, 1.f};
  GLuint zero[4] = {0, 0, 0, 0};
  float depth_clear = 0.f;
  glClearBufferfv(GL_COLOR, 0, bg);
  glClearBufferuiv(GL_COLOR, 1, zero);
  glClearBufferfv(GL_DEPTH, 0, &depth_clear);
}

// Binds the program, its uniforms from the camera (view_proj, light, eye),
// the colour texture and the vertex array.
void bind_draw_state(GLuint program, GLuint color_tex, GLuint vao, const Camera& cam, double ambient) {
  glUseProgram(program);
  Eigen::Matrix4f vp = (cam.projection() * cam.view()).cast<float>();
  glUniformMatrix4fv(glGetUniformLocation(program, "view_proj"), 1, GL_FALSE, vp.data());  // column-major
  const Eigen::Vector3d L = key_light(cam);
  glUniform3f(glGetUniformLocation(program, "light_dir"), float(L.x()), float(L.y()), float(L.z()));
  glUniform3f(glGetUniformLocation(program, "eye"), float(cam.eye.x()), float(cam.eye.y()), float(cam.eye.z()));
  glUniform1f(glGetUniformLocation(program, "ambient"), float(ambient));
  glUniform1i(glGetUniformLocation(program, "colors"), 0);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_BUFFER, color_tex);
  glBindVertexArray(vao);
}

// Draws triangles [first, end) in one call (base: the index gl_PrimitiveID
// restarts from), adding their count to drawn.
void draw_range(GLint base, size_t first, size_t end, size_t& drawn) {
  drawn += end - first;
  glUniform1ui(base, GLuint(first));
  glDrawElements(GL_TRIANGLES, GLsizei(3 * (end - first)), GL_UNSIGNED_INT,
                 reinterpret_cast<const void*>(3 * first * sizeof(uint32_t)));
}

// The side planes of the clip volume, -w <= x, y <= w, from the rows of
// view_proj (in double), widened by two pixels; and the near and far planes
// as eye depths along the view, widened by 1e-4 of their own.
struct SidePlanes {
  Eigen::Vector4d p[4];
  Eigen::Vector3d eye, forward;
  double near_depth = 0, far_depth = 0;
};
SidePlanes side_planes(const Camera& cam) {
  const Eigen::Matrix4d m = cam.projection() * cam.view();
  const double wx = 1.0 + 4.0 / cam.width, wy = 1.0 + 4.0 / cam.height;
  return {{wx * m.row(3).transpose() + m.row(0).transpose(), wx * m.row(3).transpose() - m.row(0).transpose(),
           wy * m.row(3).transpose() + m.row(1).transpose(), wy * m.row(3).transpose() - m.row(1).transpose()},
          cam.eye,
          cam.forward,
          cam.znear * (1 - 1e-4),
          cam.zfar * (1 + 1e-4)};
}

// Whether a chunk's box may be in view. A box is skipped when even its
// corner farthest along a plane's normal lies outside by more than the float
// rounding of the shader's clip coordinates (1e-5 of the terms' magnitudes,
// about 80 float epsilons): coordinates far from the origin never lose a
// triangle the GPU draws.
bool box_visible(const SidePlanes& planes, const Bounds& b) {
  // Wholly nearer than the near plane or beyond the far one: its triangles
  // are clipped away (a view framed on one building of a district).
  double dmin = 0, dmax = 0;
  for (int k = 0; k < 3; ++k) {
    const double f = planes.forward[k], lo = double(b.lo[k]) - planes.eye[k], hi = double(b.hi[k]) - planes.eye[k];
    dmin += f * (f >= 0 ? lo : hi);
    dmax += f * (f >= 0 ? hi : lo);
  }
  if (dmax < planes.near_depth || dmin > planes.far_depth) return false;
  for (const auto& pl : planes.p) {
    double v = pl[3], mag = std::fabs(pl[3]);
    for (int k = 0; k < 3; ++k) {
      v += pl[k] * double(pl[k] >= 0 ? b.hi[k] : b.lo[k]);
      mag += std::fabs(pl[k]) * std::max(std::fabs(double(b.lo[k])), std::fabs(double(b.hi[k])));
    }
    if (v < -1e-5 * mag) return false;
  }
  return true;
}

// Draws the runs of consecutive chunks whose boxes may be in view, one draw
// each, in order.
void draw_visible_chunks(const Camera& cam, const std::vector<Bounds>& chunk_box,
                         size_t chunk_triangles, size_t triangle_count, GLint base, size_t& drawn) {
  const SidePlanes planes = side_planes(cam);
  size_t run = 0;  // first chunk of the current run of visible chunks
  const size_t chunks = chunk_box.size();
  for (size_t c = 0; c <= chunks; ++c) {
    if (c < chunks && box_visible(planes, chunk_box[c])) continue;
    if (c > run) draw_range(base, run * chunk_triangles, std::min(c * chunk_triangles, triangle_count), drawn);
    run = c + 1;
  }
}

// Turns a w x h image read from GL upside down (GL rows are bottom-up).
template <class V>
void flip_rows(V& v, int w, int h) {
  for (int y = 0; y < h / 2; ++y)
    std::swap_ranges(v.begin() + long(y) * w, v.begin() + long(y + 1) * w, v.begin() + long(h - 1 - y) * w);
}

// The part of the framebuffer a render reads: x, y from its bottom-left
// corner (GL's), w x h pixels.
struct GlRect {
  int x = 0, y = 0, w = 0, h = 0;
};

// Reads the colour attachment's `r` into rgb (row 0 top), through the RGBA scratch.
void read_colors(const GlRect& r, std::vector<uint8_t>& rgba, std::vector<uint8_t>& rgb) {
  const size_t w = size_t(r.w), h = size_t(r.h);
  rgba.resize(w * h * 4);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(r.x, r.y, r.w, r.h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  rgb.resize(w * h * 3);
  for (size_t y = 0; y < h; ++y) {  // GL rows are bottom-up
    const uint8_t* src = rgba.data() + (h - 1 - y) * w * 4;
    uint8_t* dst = rgb.data() + y * w * 3;
    for (size_t x = 0; x < w; ++x, src += 4, dst += 3) dst[0] = src[0], dst[1] = src[1], dst[2] = src[2];
  }
}

// Reads the ID attachment's `r` into ids (row 0 top).
void read_ids(const GlRect& r, std::vector<uint32_t>& ids) {
  ids.resize(size_t(r.w) * r.h);
  glReadBuffer(GL_COLOR_ATTACHMENT1);
  glReadPixels(r.x, r.y, r.w, r.h, GL_RED_INTEGER, GL_UNSIGNED_INT, ids.data());
  flip_rows(ids, r.w, r.h);
}

// Reads the depth buffer's `r` (through the scratch z) into eye depth in
// metres, row 0 top, 0 for the background.
void read_depth(const Camera& cam, const GlRect& r, std::vector<float>& z, std::vector<float>& depth) {
  z.resize(size_t(r.w) * r.h);
  glReadPixels(r.x, r.y, r.w, r.h, GL_DEPTH_COMPONENT, GL_FLOAT, z.data());
  flip_rows(z, r.w, r.h);
  // Reversed-Z window depth -> eye depth: z_w = n (f - d) / (d (f - n))  =>  d = n f / (z_w (f - n) + n).
  double n = cam.znear, f = cam.zfar;
  depth.resize(z.size());
  for (size_t i = 0; i < z.size(); ++i) depth[i] = z[i] > 0 ? float(n * f / (z[i] * (f - n) + n)) : 0.f;
}

// The part of the frame RenderOptions asks for, in GL's coordinates.
GlRect part_of(const Camera& cam, const RenderOptions& opt) {
  if (opt.part_w == 0) return {0, 0, cam.width, cam.height};
  if (opt.part_x < 0 || opt.part_y < 0 || opt.part_w < 1 || opt.part_h < 1 ||
      int64_t(opt.part_x) + opt.part_w > cam.width || int64_t(opt.part_y) + opt.part_h > cam.height)
    throw RenderError("part " + std::to_string(opt.part_w) + "x" + std::to_string(opt.part_h) + " at (" +
                      std::to_string(opt.part_x) + ", " + std::to_string(opt.part_y) + ") is not inside the " +
                      std::to_string(cam.width) + "x" + std::to_string(cam.height) + " frame");
  return {opt.part_x, cam.height - opt.part_y - opt.part_h, opt.part_w, opt.part_h};
}

}  // namespace

void Renderer::render(const Camera& cam, RenderOutput& out, const RenderOptions& opt) {
  Impl& I = *impl_;
  if (!I.has_scene) throw RenderError("render() before set_scene()");
  if (cam.width <= 0 || cam.height <= 0 || cam.width > 16384 || cam.height > 16384)
    throw RenderError("bad image size " + std::to_string(cam.width) + "x" + std::to_string(cam.height));
  auto t0 = std::chrono::steady_clock::now();
  I.make_current();
  I.fit(cam.width, cam.height);
  I.select_colors(opt);

  const GlRect part = part_of(cam, opt);
  // The whole framebuffer is cleared (llvmpipe clears whole tiles at once; a
  // scissored clear draws a quad, slower than clearing twice the area), the
  // draw scissored to the part.
  clear_framebuffer(I.fbo, cam, opt.background);
  const bool scissor = part.w != cam.width || part.h != cam.height;
  if (scissor) {
    glEnable(GL_SCISSOR_TEST);
    glScissor(part.x, part.y, part.w, part.h);
  }
  bind_draw_state(I.program, I.color_tex, I.vao, cam, opt.ambient);
  const GLint base = glGetUniformLocation(I.program, "base");
  out.drawn_triangles = 0;
  if (!opt.cull)
    draw_range(base, 0, I.triangle_count, out.drawn_triangles);
  else
    draw_visible_chunks(cam, I.chunk_box, Impl::kChunkTriangles, I.triangle_count, base, out.drawn_triangles);
  if (scissor) glDisable(GL_SCISSOR_TEST);

  out.width = part.w;
  out.height = part.h;
  read_colors(part, I.rgba, out.rgb);
  out.ids.clear();
  out.depth.clear();
  if (opt.want_ids) read_ids(part, out.ids);
  if (opt.want_depth) read_depth(cam, part, I.z, out.depth);
  if (GLenum err = glGetError(); err != GL_NO_ERROR)
    throw RenderError("OpenGL error " + std::to_string(err) + " while rendering");
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<uint8_t> shade_ids(const Scene& scene, const Camera& cam, const std::vector<uint32_t>& ids,
                               const std::vector<float>& colors, const RenderOptions& opt) {
  const size_t nt = scene.triangle_count();
  if (ids.size() != size_t(cam.width) * size_t(cam.height))
    throw RenderError("shade_ids: the ID buffer is not the camera's size");
  if (colors.size() != 3 * nt) throw RenderError("shade_ids: triangle_colors must hold 3 floats per triangle");
  // The fragment shader's light and its float -> 8-bit conversion (round to nearest).
  const Eigen::Vector3d L = key_light(cam);
  auto corner = [&](size_t t, int k) {
    const float* p = &scene.positions[3 * size_t(scene.indices[3 * t + k])];
    return Eigen::Vector3d(p[0], p[1], p[2]);
  };
  auto unorm8 = [](double c) { return uint8_t(std::lround(std::clamp(c, 0.0, 1.0) * 255.0)); };
  std::vector<uint8_t> rgb(3 * ids.size());
  uint32_t last = 0;
  uint8_t shaded[3] = {opt.background[0], opt.background[1], opt.background[2]};
  for (size_t i = 0; i < ids.size(); ++i) {
    const uint32_t id = ids[i];
    if (id == 0 || id > nt) {
      for (int k = 0; k < 3; ++k) rgb[3 * i + k] = opt.background[k];
      continue;
    }
    if (id != last) {  // neighbouring pixels mostly show the same triangle
      const size_t t = id - 1;
      const Eigen::Vector3d a = corner(t, 0);
      Eigen::Vector3d n = (corner(t, 1) - a).cross(corner(t, 2) - a);
      const double len = n.norm();
      double diffuse = 0;
      if (len > 0) {
        n /= len;
        if (n.dot(cam.eye - a) < 0) n = -n;
        diffuse = std::max(n.dot(L), 0.0);
      }
      const double shade = opt.ambient + (1.0 - opt.ambient) * diffuse;
      for (int k = 0; k < 3; ++k) shaded[k] = unorm8(double(colors[3 * t + k]) * shade);
      last = id;
    }
    for (int k = 0; k < 3; ++k) rgb[3 * i + k] = shaded[k];
  }
  return rgb;
}

}  // namespace perclod
