// The key tables of docs/usage.md (#config-keys, #display-profiles) are the
// tables of settings (perclod/settings.h): the same keys, and for each its
// type, default and allowed values. A key added to the code without its row,
// a row left behind, or a default changed on one side only fails here. And
// the CLI options that set a config key show the table's help.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_util.h"
#include "perclod/settings.h"

namespace perclod {
namespace {

struct Row {
  std::string key, type, default_text, allowed, help;
};

// A cell as plain text: links as their text, code spans as their content.
std::string plain(std::string cell) {
  cell = std::regex_replace(cell, std::regex(R"(\[([^\]]*)\]\([^)]*\))"), "$1");
  std::string out;
  for (char ch : cell)
    if (ch != '`') out += ch;
  const size_t b = out.find_first_not_of(' '), e = out.find_last_not_of(' ');
  return b == std::string::npos ? "" : out.substr(b, e - b + 1);
}

// The cells of a markdown table row "| a | b |".
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> c;
  size_t start = 1;
  for (size_t bar; (bar = line.find('|', start)) != std::string::npos; start = bar + 1)
    c.push_back(line.substr(start, bar - start));
  return c;
}

// The rows of the first table under `heading` ("## Config keys"), up to the next heading.
std::vector<Row> docs_table(const std::string& markdown, const std::string& heading) {
  std::istringstream in(markdown);
  std::vector<Row> rows;
  bool under = false, header_seen = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("#", 0) == 0) {
      if (under) break;
      under = line == heading;
      continue;
    }
    if (!under) continue;
    if (line.rfind("|", 0) != 0) {
      if (header_seen && !rows.empty()) break;  // the table ended
      continue;
    }
    std::vector<std::string> c = cells(line);
    if (!header_seen) {  // "| key | type | ..." then "|---|..."
      header_seen = true;
      continue;
    }
    if (line.rfind("|---", 0) == 0) continue;
    c.resize(5);
    rows.push_back({plain(c[0]), plain(c[1]), plain(c[2]), plain(c[3]), plain(c[4])});
  }
  return rows;
}

std::string read_usage() {
  std::ifstream f(std::string(PERCLOD_SOURCE_DIR) + "/docs/usage.md");
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// The row the table of settings gives `s`, to paste into docs/usage.md.
std::string row_of(const SettingSpec& s) {
  return std::string("| `") + s.key + "` | " + s.type + " | " + s.default_text + " | " + s.allowed + " | " + s.help +
         " |";
}

void expect_docs_match(const std::vector<Row>& rows, const std::vector<SettingSpec>& table, const std::string& heading) {
  ASSERT_FALSE(rows.empty()) << "docs/usage.md has no table under '" << heading << "'";
  std::map<std::string, Row> docs;
  for (const Row& r : rows) EXPECT_TRUE(docs.emplace(r.key, r).second) << heading << ": `" << r.key << "` twice";
  std::set<std::string> code;
  for (const SettingSpec& s : table) {
    code.insert(s.key);
    auto it = docs.find(s.key);
    if (it == docs.end()) {
      ADD_FAILURE() << heading << " lacks `" << s.key << "`; its row from the code:\n" << row_of(s);
      continue;
    }
    const Row& r = it->second;
    EXPECT_EQ(r.default_text, s.default_text) << heading << ", `" << s.key << "`: the default differs from the code";
    EXPECT_EQ(r.type, s.type) << heading << ", `" << s.key << "`: the type differs from the code";
    EXPECT_EQ(r.allowed, s.allowed) << heading << ", `" << s.key << "`: the allowed values differ from the code";
    EXPECT_FALSE(r.help.empty()) << heading << ", `" << s.key << "` says nothing";
  }
  for (const Row& r : rows)
    EXPECT_TRUE(code.count(r.key)) << heading << " has `" << r.key << "`, a key the code does not read";
}

TEST(SettingsDocs, ConfigKeysTableIsTheCodes) {
  expect_docs_match(docs_table(read_usage(), "## Config keys"), config_settings(), "## Config keys");
}

TEST(SettingsDocs, DisplayProfilesTableIsTheCodes) {
  expect_docs_match(docs_table(read_usage(), "## Display profiles"), display_settings(), "## Display profiles");
}

// The parser finds what a table holds and stops at its end, so the checks
// above cannot pass on a table it misread.
TEST(SettingsDocs, ParserReadsRowsAndStopsAtTheTablesEnd) {
  const std::string md =
      "## Other\n| key | type |\n|---|---|\n| `x` | y |\n"
      "## Config keys\n\nText.\n\n| key | type | default | allowed | what it does |\n|---|---|---|---|---|\n"
      "| `ratio` | number | 0.5 | 0..1 | See [Samples](#samples). |\n"
      "| `out` | path | `out` | | Output. |\n\nAfter.\n| `late` | a | b | c | d |\n## Next\n";
  const std::vector<Row> rows = docs_table(md, "## Config keys");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].key, "ratio");
  EXPECT_EQ(rows[0].default_text, "0.5");
  EXPECT_EQ(rows[0].help, "See Samples.");
  EXPECT_EQ(rows[1].default_text, "out");
  EXPECT_EQ(rows[1].allowed, "");
  EXPECT_TRUE(docs_table(md, "## Display profiles").empty());
}

// Text with every run of whitespace one space (CLI11 indents wrapped help).
std::string words(const std::string& text) {
  std::istringstream in(text);
  std::string out;
  for (std::string w; in >> w;) out += (out.empty() ? "" : " ") + w;
  return out;
}

TEST(SettingsDocs, CliOptionsShowTheTablesHelp) {
  const std::vector<std::pair<std::string, std::vector<const char*>>> commands = {
      {"run", {"views", "samples", "keep_unsampled_surface", "mask_per_sample", "combine_views", "strict", "explain",
               "jobs", "memory_budget_mb"}},
      {"label", {"up", "scale", "cityjson_lod", "display", "views", "samples", "keep_unsampled_surface",
                 "mask_per_sample", "spins", "per_building", "tracer", "verify", "ratio", "combine_views"}},
      {"simplify", {"simplify", "target", "e_perceptible", "e_imperceptible", "e_undisplayable", "k",
                    "keep_undisplayable", "format", "explain"}},
      {"render", {"views"}},
  };
  for (const auto& [command, keys] : commands) {
    const test::CliResult r = test::run_cli(command + " --help");
    ASSERT_EQ(r.exit_code, 0) << command << ": " << r.err;
    const std::string help = words(r.out);
    for (const char* key : keys)
      EXPECT_NE(help.find(words(config_setting(key).help)), std::string::npos)
          << command << " --help lacks the help of " << key << ":\n" << r.out;
  }
  EXPECT_EQ(words(" a\n   b  c "), "a b c");
}

}  // namespace
}  // namespace perclod
