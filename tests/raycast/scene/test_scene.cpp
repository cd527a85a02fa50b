// The Scene contract: validate() accepts what scene.h promises and names
// the first rule a scene breaks; component_of/material_of apply the rule for
// empty per-triangle arrays.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "perclod/scene.h"

namespace perclod {
namespace {

// Two triangles, two components, one material.
Scene two_triangles() {
  Scene s;
  s.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  s.indices = {0, 1, 2, 1, 3, 2};
  s.component = {0, 1};
  s.component_names = {"a", "b"};
  s.material = {0, 0};
  s.materials = {Material{"red", {1, 0, 0}, true}};
  return s;
}

std::string error_of(const Scene& s) {
  try {
    validate(s);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(SceneContract, AcceptsAFullSceneAndOneWithoutComponentOrMaterialArrays) {
  Scene s = two_triangles();
  EXPECT_EQ(error_of(s), "");
  EXPECT_EQ(s.component_of(1), 1u);
  ASSERT_NE(s.material_of(1), nullptr);
  EXPECT_EQ(s.material_of(1)->name, "red");
  s.component.clear();
  s.material.clear();
  EXPECT_EQ(error_of(s), "");
  EXPECT_EQ(s.component_of(1), 0u);       // one component
  EXPECT_EQ(s.material_of(1), nullptr);   // the default material
  EXPECT_EQ(error_of(Scene{}), "");       // the empty scene
}

TEST(SceneContract, NamesTheBrokenRule) {
  auto expect = [](const Scene& s, const std::string& part) {
    std::string e = error_of(s);
    EXPECT_EQ(e.rfind("scene: ", 0), 0u) << e;
    EXPECT_NE(e.find(part), std::string::npos) << e;
  };
  Scene s = two_triangles();
  s.positions.pop_back();
  expect(s, "positions size 11");
  s = two_triangles();
  s.indices.pop_back();
  expect(s, "indices size 5");
  s = two_triangles();
  s.indices[4] = 9;
  expect(s, "triangle 1 uses vertex 9");
  s = two_triangles();
  s.positions[7] = NAN;
  expect(s, "vertex 2 is not finite");
  s = two_triangles();
  s.positions[0] = INFINITY;
  expect(s, "vertex 0 is not finite");
  s = two_triangles();
  s.component.pop_back();
  expect(s, "1 component ids for 2 triangles");
  s = two_triangles();
  s.material.push_back(0);
  expect(s, "3 material ids for 2 triangles");
  s = two_triangles();
  s.component[1] = 2;
  expect(s, "triangle 1 has component 2 but there are only 2 component names");
  s = two_triangles();
  s.material[0] = 1;
  expect(s, "triangle 0 has material 1 but there are only 1 materials");
}

}  // namespace
}  // namespace perclod
