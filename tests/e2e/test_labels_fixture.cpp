// The paper's labelling is kept exactly: the four facade views with one sample
// per pixel give, on the bundled building at 56 m, the labels file the code
// wrote before view sets, framing and samples existed (committed fixture,
// written by perclod label at commit d15d02b).
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "../pipeline/test_util.h"
#include "perclod/load.h"
#include "perclod/pipeline.h"

namespace perclod {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

TEST(PaperLabels, FacadesAtOneSamplePerPixelMatchTheFixtureBitForBit) {
  const std::string model = std::string(PERCLOD_SOURCE_DIR) + "/data/ingolstadt/bldg_4018215.obj";
  const std::string fixture =
      std::string(PERCLOD_SOURCE_DIR) + "/tests/e2e/fixtures/bldg_4018215_labels_56m_facades_1spp.txt";
  test::TempDir dir("paper-labels");
  Scene s = load_scene(model);
  LabelJob job;
  job.up = UpAxis::Z;
  job.display = DisplayProfile{};
  job.perception = perception_settings_for(job.display);
  job.views = parse_views("facades", UpAxis::Z);
  job.samples = 1;
  job.per_building = PerBuilding::Off;
  job.distance = 56;
  job.write_perception_images = false;
  job.out = output_names_for(dir.path.string(), model);
  label_model(s, job, TracerKind::Octree);
  const std::string got = slurp(job.out.labels(56)), want = slurp(fixture);
  ASSERT_FALSE(want.empty()) << fixture;
  EXPECT_TRUE(got == want) << "labels differ from " << fixture;
}

}  // namespace
}  // namespace perclod
