// Issue 12 (reliability): hostile model and image files fail fast, with the
// file's name and what is wrong, instead of crashing, hanging or allocating
// what the header claims.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "perclod/export.h"
#include "perclod/image_io.h"
#include "perclod/load.h"
#include "perclod/outputs.h"
#include "test_util.h"

using namespace perclod;
namespace fs = std::filesystem;

namespace {

std::string load_error(const std::string& path, const LoadOptions& opt = {}) {
  try {
    load_scene(path, opt);
  } catch (const LoadError& e) {
    return e.what();
  }
  return "";
}

using test::has;

// A binary little-endian PLY of test::box(): 8 float vertices, 6 quads (uchar count, int indices).
std::string binary_ply_cube() {
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
      "property float z\nelement face 6\nproperty list uchar int vertex_indices\nend_header\n";
  Scene b = test::box();
  for (float f : b.positions) ply.append(reinterpret_cast<const char*>(&f), 4);
  const int32_t quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  for (auto& q : quads) {
    ply += char(4);
    ply.append(reinterpret_cast<const char*>(q), 16);
  }
  return ply;
}

std::string write_binary(const test::TempDir& dir, const std::string& name, const std::string& bytes) {
  std::string p = dir / name;
  std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
  return p;
}

uint32_t crc32(const std::string& s, size_t from, size_t to) {
  uint32_t c = 0xFFFFFFFFu;
  for (size_t i = from; i < to; ++i) {
    c ^= uint8_t(s[i]);
    for (int k = 0; k < 8; ++k) c = c & 1 ? (c >> 1) ^ 0xEDB88320u : c >> 1;
  }
  return ~c;
}

void put_be32(std::string& s, size_t at, uint32_t v) {
  for (int k = 0; k < 4; ++k) s[at + k] = char(v >> (24 - 8 * k));
}

}  // namespace

// ------------------------------------------------------------ items 2, 3, 7, 8: model files

TEST(HostileInputs, TruncatedBinaryPlyIsAnErrorNotACrash) {
  test::TempDir dir("ply");
  const std::string whole = binary_ply_cube();
  ASSERT_EQ(whole.size(), 367u);
  EXPECT_EQ(load_scene(write_binary(dir, "cube.ply", whole)).triangle_count(), 12u);
  for (size_t cut : {337u, 300u, 250u}) {
    std::string p = write_binary(dir, "cut" + std::to_string(cut) + ".ply", whole.substr(0, cut));
    std::string m = load_error(p);
    EXPECT_TRUE(has(m, p + ": ")) << cut << ": " << m;
  }
}

TEST(HostileInputs, PlyDeclaringMoreElementsThanItsSizeFailsFast) {
  test::TempDir dir("ply-huge");
  auto p = dir.file("huge.ply",
                    "ply\nformat ascii 1.0\nelement vertex 100000000\nproperty float x\nproperty float y\n"
                    "property float z\nend_header\n");
  auto t0 = std::chrono::steady_clock::now();
  std::string m = load_error(p);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  EXPECT_TRUE(has(m, p + ": PLY header declares 100000000 vertex elements")) << m;
  // Binary: 8 vertices of 12 bytes declared, 50 bytes given.
  std::string ply = binary_ply_cube();
  ply = ply.substr(0, ply.find("end_header\n") + 11) + std::string(50, '\0');
  auto q = write_binary(dir, "short.ply", ply);
  m = load_error(q);
  EXPECT_TRUE(has(m, q + ": PLY header declares")) << m;
}

// The 10-minute fuzz run's finding: assimp's PLY reader never returned on a
// garbled header line. perclod now checks every header line first.
TEST(HostileInputs, GarbledPlyHeaderIsRefusedBeforeAssimpReadsIt) {
  test::TempDir dir("ply-header");
  const std::string finding = std::string(PERCLOD_SOURCE_DIR) + "/tests/fuzz/findings/fuzz_assimp/timeout-ply-header-hang-2.ply";
  std::string m = load_error(finding);
  EXPECT_TRUE(has(m, finding + ": PLY file without an 'end_header' line")) << m;  // its end_header follows binary bytes
  // The garbled line itself, in a header that does end:
  std::string garbled = dir.file("garbled.ply", "ply\nformat ascii 1.0\nesectionlement vertex 3\nend_header\n");
  m = load_error(garbled);
  EXPECT_TRUE(has(m, garbled + ": PLY header line 3: 'esectionlement' is not a PLY header keyword")) << m;
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\n";
  const std::string tail = "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
  EXPECT_EQ(load_scene(dir.file("ok.ply", head + xyz + tail)).triangle_count(), 1u);
  const std::pair<std::string, std::string> cases[] = {
      {"property float x\nproperty flot y\nproperty float z\n", "line 5: unknown property type 'flot'"},
      {"property float x\nproperty float\nproperty float z\n", "line 5: property without a name"},
      {"property float x\nproperty float y\xff\nproperty float z\n", "line 5: non-ASCII byte"},
      {xyz + "propertyy float w\n", "line 7: 'propertyy' is not a PLY header keyword"},
      {xyz + "comment anything \xff goes\n", ""},
  };
  for (const auto& [props, want] : cases) {
    auto p = dir.file("case.ply", head + props + tail);
    if (want.empty()) {
      EXPECT_EQ(load_scene(p).triangle_count(), 1u);
      continue;
    }
    m = load_error(p);
    EXPECT_TRUE(has(m, p + ": PLY header " + want)) << m;
  }
  // The same run's second finding: "ply?" on the first line, picked by its extension.
  const std::string magic = std::string(PERCLOD_SOURCE_DIR) + "/tests/fuzz/findings/fuzz_assimp/timeout-ply-magic-hang.ply";
  m = load_error(magic);
  EXPECT_TRUE(has(m, magic + ": PLY file without an 'end_header' line")) << m;
  // The third: "end_header" inside the format line, never as a line of its own.
  const std::string inline_end = std::string(PERCLOD_SOURCE_DIR) + "/tests/fuzz/findings/fuzz_assimp/timeout-ply-end-header-hang.ply";
  m = load_error(inline_end);
  EXPECT_TRUE(has(m, inline_end + ": PLY file without an 'end_header' line")) << m;
  m = load_error(dir.file("q.ply", "ply?\nformat ascii 1.0\nelement vertex 0\nend_header\n"));
  EXPECT_TRUE(has(m, "PLY header line 1: expected 'ply'")) << m;
  m = load_error(dir.file("fmt.ply", "ply\nformat text 1.0\n" + std::string("element vertex 0\nend_header\n")));
  EXPECT_TRUE(has(m, "line 2: unknown format 'text'")) << m;
}

TEST(HostileInputs, GlbWithACorruptChunkLengthFailsFast) {
  test::TempDir dir("glb");
  const std::string good = dir / "box.glb";
  export_scene(test::box(), good);
  ASSERT_EQ(load_scene(good).triangle_count(), 12u);
  std::ifstream f(good, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(f)), {});
  bytes[12] = '\xff', bytes[13] = '\xff', bytes[14] = '\xff';  // JSON chunk length ~16 MB
  auto p = write_binary(dir, "bad.glb", bytes);
  auto t0 = std::chrono::steady_clock::now();
  std::string m = load_error(p);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  EXPECT_TRUE(has(m, p + ": GLB chunk 0 declares")) << m;
  m = load_error(write_binary(dir, "cut.glb", bytes.substr(0, 40)));
  EXPECT_TRUE(has(m, "truncated or corrupt")) << m;
}

TEST(HostileInputs, ModelWithoutExtensionIsReadAsObjInDouble) {
  test::TempDir dir("noext");
  // Source coordinates where float keeps 0.5 m steps only: double keeps the millimetres.
  auto p = dir.file("model", "# no extension\nv 678000.001 5403500.001 0\nv 678001.001 5403500.001 0\n"
                             "v 678000.001 5403501.001 0\nf 1 2 3\n");
  Scene s = load_scene(p);
  ASSERT_EQ(s.triangle_count(), 1u);
  EXPECT_NEAR(s.offset[0] + s.positions[0], 678000.001, 1e-6);
  EXPECT_NEAR(s.offset[1] + s.positions[1], 5403500.001, 1e-6);
}

// ------------------------------------------------------------ items 4, 5: OBJ values

TEST(HostileInputs, FloatOverflowIsRefusedNamingTheFile) {
  test::TempDir dir("overflow");
  auto p = dir.file("big.obj", "v 1e39 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n");
  std::string m = load_error(p);
  EXPECT_TRUE(has(m, p + ": vertex 1 coordinate 1e+39")) << m;
  EXPECT_TRUE(has(m, "too large or the unit scale is wrong")) << m;
  auto q = dir.file("small.obj", "v 10 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n");
  m = load_error(q, LoadOptions{1e300});
  EXPECT_TRUE(has(m, q + ": ")) << m;
  EXPECT_TRUE(has(m, "unit scale 1e+300")) << m;
  m = load_error(q, LoadOptions{1e308});  // overflows double itself
  EXPECT_TRUE(has(m, q + ": coordinates overflow")) << m;
}

TEST(HostileInputs, ObjJunkAfterNumbersIsRefusedWithTheLine) {
  test::TempDir dir("junk");
  const std::string verts = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  for (const char* face : {"f 1.5 2 3", "f 1 2x 3", "f 1 2 3/", "f 1/1x 2 3", "f 1/2/3/4 2 3", "f 1//x 2 3",
                           "f 1/ 2 3", "f 1/2/ 2 3", "f 1/// 2 3"}) {
    auto p = dir.file("f.obj", verts + face + "\n");
    std::string m = load_error(p);
    EXPECT_TRUE(has(m, p + ":4: face corner")) << face << ": " << m;
  }
  for (const char* ok : {"f 1 2 3", "f 1/1 2/2 3/3", "f 1//1 2//2 3//3", "f 1/1/1 2/2/2 3/3/3", "f -3 -2 -1"})
    EXPECT_EQ(load_scene(dir.file("ok.obj", verts + ok + "\n")).triangle_count(), 1u) << ok;
  auto p = dir.file("v.obj", "v 1 2 3abc\n");
  std::string m = load_error(p);
  EXPECT_TRUE(has(m, p + ":1: vertex coordinate '3abc' is not a number")) << m;
}

// ------------------------------------------------------------ item 6: image sizes

TEST(HostileInputs, PngDeclaringAHugeSizeIsRefusedBeforeAllocating) {
  test::TempDir dir("png-huge");
  const std::string small = dir / "small.png";
  std::vector<uint8_t> px(4 * 4 * 3, 200);
  write_png(small, 4, 4, 3, px.data());
  std::ifstream f(small, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(f)), {});
  ASSERT_EQ(bytes.compare(12, 4, "IHDR"), 0);
  put_be32(bytes, 16, 60000);  // width
  put_be32(bytes, 20, 60000);  // height
  put_be32(bytes, 29, crc32(bytes, 12, 29));
  auto p = write_binary(dir, "huge.png", bytes);
  try {
    read_rgb8(p);
    FAIL() << "a 60000x60000 PNG of " << bytes.size() << " bytes was read";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(has(e.what(), p + ": image size 60000x60000")) << e.what();
  }
  // Within the limits but more than the file's bytes can hold.
  put_be32(bytes, 16, 8000);
  put_be32(bytes, 20, 8000);
  put_be32(bytes, 29, crc32(bytes, 12, 29));
  p = write_binary(dir, "big.png", bytes);
  try {
    read_rgb8(p);
    FAIL() << "an 8000x8000 PNG of " << bytes.size() << " bytes was read";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(has(e.what(), p + ": PNG header declares 8000x8000")) << e.what();
  }
}

// ------------------------------------------------------------ item 7: big polygons

TEST(HostileInputs, AHugePolygonTriangulatesInNearLinearTime) {
  test::TempDir dir("polygon");
  // A star-shaped (concave) polygon of 100k corners.
  const int n = 100000;
  std::string obj;
  obj.reserve(size_t(n) * 40);
  for (int i = 0; i < n; ++i) {
    double a = 2 * M_PI * i / n, r = i % 2 ? 1.0 : 0.9;
    obj += "v " + std::to_string(r * std::cos(a)) + " " + std::to_string(r * std::sin(a)) + " 0\n";
  }
  obj += "f";
  for (int i = 1; i <= n; ++i) obj.append(1, ' ').append(std::to_string(i));
  obj += "\n";
  auto p = dir.file("star.obj", obj);
  auto t0 = std::chrono::steady_clock::now();
  LoadReport rep;
  Scene s = load_scene(p, {}, &rep);
  EXPECT_EQ(rep.polygons_fanned, 0u);  // clipped all the way
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(s.triangle_count(), size_t(n - 2));
  EXPECT_LT(seconds, 5.0);
  // The triangles cover the polygon exactly once: their areas sum to its area.
  double area = 0, poly = 0;
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    const float* A = &s.positions[3 * size_t(s.indices[3 * t])];
    const float* B = &s.positions[3 * size_t(s.indices[3 * t + 1])];
    const float* C = &s.positions[3 * size_t(s.indices[3 * t + 2])];
    area += 0.5 * std::fabs(double(B[0] - A[0]) * (C[1] - A[1]) - double(B[1] - A[1]) * (C[0] - A[0]));
  }
  for (int i = 0; i < n; ++i) {
    const float* A = &s.positions[3 * size_t(i)];
    const float* B = &s.positions[3 * size_t((i + 1) % n)];
    poly += 0.5 * (double(A[0]) * B[1] - double(B[0]) * A[1]);
  }
  EXPECT_NEAR(area, poly, 1e-3 * poly);
}

// A spiral band has only a few ears at a time: ear clipping alone is O(n^2)
// (over 140 s for 100k corners). The work budget bounds it; the rest is a fan.
TEST(HostileInputs, AHugeSpiralPolygonStillLoadsQuickly) {
  test::TempDir dir("spiral");
  const int half = 50000;
  std::string obj;
  for (int side = 0; side < 2; ++side)
    for (int k = 0; k < half; ++k) {
      int i = side == 0 ? k : half - 1 - k;
      double a = i * 0.01, r = 1 + a * 0.5 - (side ? 0.2 : 0.0);
      obj.append("v ").append(std::to_string(r * std::cos(a))).append(" ");
      obj.append(std::to_string(r * std::sin(a))).append(" 0\n");
    }
  obj += "f";
  for (int i = 1; i <= 2 * half; ++i) obj.append(1, ' ').append(std::to_string(i));
  obj += "\n";
  auto p = dir.file("spiral.obj", obj);
  auto t0 = std::chrono::steady_clock::now();
  LoadReport rep;
  Scene s = load_scene(p, {}, &rep);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  EXPECT_EQ(s.triangle_count(), size_t(2 * half - 2));
  EXPECT_EQ(rep.polygons_fanned, 1u);  // reported, for `perclod info` and the load message
}
