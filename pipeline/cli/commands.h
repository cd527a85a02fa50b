// The perclod CLI: one register_* function per subcommand, each in cmd_<name>.cpp.
// A command parses its options, calls perclod_pipeline and prints; it holds no algorithm.
#pragma once

#include <CLI/CLI.hpp>

namespace perclod::cli {

void register_info(CLI::App& app);
void register_render(CLI::App& app);
void register_generate(CLI::App& app);
void register_perceive(CLI::App& app);
void register_label(CLI::App& app);
void register_simplify(CLI::App& app);
void register_run(CLI::App& app);
void register_judge(CLI::App& app);

}  // namespace perclod::cli
