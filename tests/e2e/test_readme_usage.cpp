// Every usage line of README.md's "## Usage" block names a real command, and
// every option it shows is one that command's --help lists: the README's
// usage stays true as the CLI changes.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "cli_util.h"

namespace perclod {
namespace {

// The lines starting with "build/perclod" in the first ```sh block after "## Usage".
std::vector<std::string> usage_lines() {
  std::ifstream f(std::string(PERCLOD_SOURCE_DIR) + "/README.md");
  std::string line;
  bool in_usage = false, in_block = false;
  std::vector<std::string> lines;
  while (std::getline(f, line)) {
    if (line.rfind("## ", 0) == 0) in_usage = line == "## Usage";
    if (!in_usage) continue;
    if (line.rfind("```", 0) == 0) {
      if (in_block) break;
      in_block = true;
      continue;
    }
    if (in_block && line.rfind("build/perclod", 0) == 0) lines.push_back(line.substr(0, line.find('#')));
  }
  return lines;
}

struct Usage {
  std::string command;              // "label", "generate facade", or "" for the program itself
  std::vector<std::string> options;  // "--json", "-d", ...
};

Usage parse(const std::string& line) {
  std::istringstream in(line);
  std::string word;
  in >> word;  // build/perclod
  Usage u;
  bool in_command = true;
  while (in >> word) {
    if (in_command && std::regex_match(word, std::regex("[a-z]+"))) {
      u.command += (u.command.empty() ? "" : " ") + word;
      continue;
    }
    in_command = false;
  }
  static const std::regex option(R"((^|[\s\[|])(--?[A-Za-z][A-Za-z0-9-]*))");
  for (std::sregex_iterator it(line.begin(), line.end(), option), end; it != end; ++it)
    u.options.push_back((*it)[2]);
  return u;
}

// True when `help` lists `option` as an option name (CLI11 prints "-d,--distance FLOAT").
bool lists(const std::string& help, const std::string& option) {
  return std::regex_search(help, std::regex("(^|[\\s,])" + option + "([\\s,=]|$)"));
}

TEST(ReadmeUsage, EveryUsageLineIsACommandWhoseHelpListsItsOptions) {
  const std::vector<std::string> lines = usage_lines();
  ASSERT_GE(lines.size(), 8u) << "README.md's Usage block lost its command lines";
  for (const std::string& line : lines) {
    Usage u = parse(line);
    auto r = test::run_cli(u.command + " --help");
    EXPECT_EQ(r.exit_code, 0) << line << "\n" << r.err;
    for (const std::string& o : u.options) EXPECT_TRUE(lists(r.out, o)) << o << " in: " << line << "\n" << r.out;
  }
}

// The check above would pass on an empty help text if parse() found nothing:
// make sure it finds the options of a line and rejects an unknown one.
TEST(ReadmeUsage, ParsingFindsCommandAndOptions) {
  Usage u = parse("build/perclod generate facade [--floors N] -d 56 [-o DIR|--json]");
  EXPECT_EQ(u.command, "generate facade");
  EXPECT_EQ(u.options, (std::vector<std::string>{"--floors", "-d", "-o", "--json"}));
  auto r = test::run_cli("label --help");
  ASSERT_EQ(r.exit_code, 0);
  EXPECT_TRUE(lists(r.out, "-d"));
  EXPECT_TRUE(lists(r.out, "--distance"));
  EXPECT_FALSE(lists(r.out, "--no-such-option"));
}

}  // namespace
}  // namespace perclod
