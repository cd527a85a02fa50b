// The labels file (docs/usage.md#the-labels-file): the model fingerprint line and the
// mistakes read_labels must refuse instead of reading them silently.
#include <gtest/gtest.h>

#include <string>

#include "perclod/labels_io.h"
#include "test_util.h"

using namespace perclod;

namespace {

Scene triangle(float x) {
  Scene s;
  s.positions = {0, 0, 0, x, 0, 0, 0, 1, 0};
  s.indices = {0, 1, 2};
  return s;
}

// read_labels(path) must throw a message starting with "PATH:" and holding `what`.
void expect_refused(const test::TempDir& dir, const std::string& name, const std::string& text,
                    const std::string& what) {
  std::string path = dir.file(name, text);
  try {
    read_labels(path);
    ADD_FAILURE() << name << " was read";
  } catch (const std::bad_alloc&) {
    ADD_FAILURE() << name << ": bad_alloc instead of an error naming the file";
  } catch (const std::exception& e) {
    std::string msg = e.what();
    EXPECT_EQ(msg.rfind(path + ":", 0), 0u) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  }
}

}  // namespace

TEST(LabelsFile, FingerprintIsWrittenAndReadBack) {
  test::TempDir dir("labels-fp");
  EXPECT_NE(model_fingerprint(triangle(1)), model_fingerprint(triangle(2)));
  EXPECT_EQ(model_fingerprint(triangle(1)), model_fingerprint(triangle(1)));
  LabelFile f{{Label::Perceptible}, {7}, {3}, {{"+x", 56}}};
  f.has_model = true;
  f.model_triangles = 1;
  f.model_hash = 0x0123456789abcdefull;
  write_labels(dir / "l.txt", f);
  std::ifstream in(dir / "l.txt");
  std::string magic, model;
  std::getline(in, magic);
  std::getline(in, model);
  EXPECT_EQ(model, "model 1 0123456789abcdef");
  LabelFile g = read_labels(dir / "l.txt");
  EXPECT_TRUE(g.has_model);
  EXPECT_EQ(g.model_hash, f.model_hash);
  EXPECT_EQ(g.traced[0], 7u);
  EXPECT_EQ(g.imperceptible[0], 3u);
}

TEST(LabelsFile, FilesWithoutTheModelLineAreStillRead) {
  test::TempDir dir("labels-old");
  LabelFile g = read_labels(dir.file("old.txt", "perclod-labels 1\ntriangles 2\nviews 1\nview +x 56\nP 4 1\nU 0 0\n"));
  EXPECT_FALSE(g.has_model);
  ASSERT_EQ(g.labels.size(), 2u);
  EXPECT_EQ(g.labels[1], Label::Undisplayable);
}

// Words are split at any white space, as before the reader stopped using a
// stream per line: tabs, runs of spaces and CRLF line ends (a file saved on
// Windows) read the same.
TEST(LabelsFile, TabsSpacesAndCrlfLineEndsSeparateWords) {
  test::TempDir dir("labels-space");
  LabelFile g = read_labels(dir.file(
      "crlf.txt", "perclod-labels 1\r\ntriangles\t2\r\nviews 1\r\n view  +x\t56.5 \r\nI\t12   5\r\nP 3\v0\f\r\n\r\n"));
  ASSERT_EQ(g.labels.size(), 2u);
  EXPECT_EQ(g.labels[0], Label::Imperceptible);
  EXPECT_EQ(g.traced[0], 12u);
  EXPECT_EQ(g.imperceptible[0], 5u);
  EXPECT_EQ(g.labels[1], Label::Perceptible);
  EXPECT_EQ(g.traced[1], 3u);
  ASSERT_EQ(g.views.size(), 1u);
  EXPECT_EQ(g.views[0].first, "+x");
  EXPECT_EQ(g.views[0].second, 56.5);
  // A word is still one word: "P3 0" is not "P 3 0".
  const std::string head = "perclod-labels 1\ntriangles 1\nviews 0\n";
  expect_refused(dir, "glued.txt", head + "P3 0\n", "LABEL TRACED IMPERCEPTIBLE");
  expect_refused(dir, "nbsp.txt", head + "P\xc2\xa0" "3 0\n", "LABEL TRACED IMPERCEPTIBLE");
}

// The samples line: counts of a grid of samples (9, 16) read back; other
// counts are refused.
TEST(LabelsFile, SamplesLineTakesEveryPattern) {
  test::TempDir dir("labels-samples");
  for (int n : {2, 4, 8, 9, 16}) {
    LabelFile f{{Label::Perceptible}, {32}, {5}, {{"+x", 56}}};
    f.samples = n;
    write_labels(dir / "s.txt", f);
    EXPECT_EQ(read_labels(dir / "s.txt").samples, n);
  }
  expect_refused(dir, "three.txt", "perclod-labels 1\ntriangles 1\nviews 0\nsamples 3\nP 1 0\n", "samples S");
}

TEST(LabelsFile, MistakesAreRefusedNamingTheFileAndLine) {
  test::TempDir dir("labels-bad");
  const std::string head = "perclod-labels 1\ntriangles 2\nviews 0\n";
  expect_refused(dir, "neg.txt", head + "P -5 -7\nP 1 0\n", "non-negative");
  expect_refused(dir, "more.txt", head + "I 3 4\nP 1 0\n", "more imperceptible");
  expect_refused(dir, "trailing.txt", head + "P 1 0\nP 1 0\nP 1 0\n", "after the 2 triangle lines");
  expect_refused(dir, "minus.txt", "perclod-labels 1\ntriangles -1\nviews 0\n", "triangles N");
  expect_refused(dir, "huge.txt", "perclod-labels 1\ntriangles 99999999999\nviews 0\nP 1 0\n", "holds at most");
  expect_refused(dir, "short.txt", head + "P 1 0\n", "triangle 1 of 2");
  expect_refused(dir, "model.txt", "perclod-labels 1\nmodel 3 0123456789abcdef\n" + head.substr(17) + "P 1 0\nP 1 0\n",
                 "model line says 3");
  expect_refused(dir, "hash.txt", "perclod-labels 1\nmodel 2 xyz\n" + head.substr(17) + "P 1 0\nP 1 0\n",
                 "HASH");
}
