// Running the perclod binary from tests.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

namespace perclod::test {

// The demo building (data/ingolstadt/, in the repo), which most CLI tests run on.
inline const std::string kBuilding = PERCLOD_SOURCE_DIR "/data/ingolstadt/bldg_4018215.obj";

// temp/perclod-NAME-PID, emptied (removed; made again when `create`).
inline std::filesystem::path fresh_dir(const std::string& name, bool create = false) {
  std::filesystem::path p =
      std::filesystem::temp_directory_path() / ("perclod-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(p);
  if (create) std::filesystem::create_directories(p);
  return p;
}

struct CliResult {
  int exit_code = -1;
  std::string out, err;
};

// Runs `PROGRAM ARGS` through the shell; stdout and stderr captured
// separately. `shell_prefix` runs before it in the same shell (e.g.
// "ulimit -f 16;").
inline CliResult run_program(const std::string& program, const std::string& args,
                             const std::string& shell_prefix = "") {
  auto err_path = std::filesystem::temp_directory_path() / ("perclod-cli-err-" + std::to_string(::getpid()));
  std::string cmd = shell_prefix + program + " " + args + " 2>" + err_path.string();
  CliResult r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (FILE* e = fopen(err_path.c_str(), "r")) {
    while ((n = fread(buf.data(), 1, buf.size(), e)) > 0) r.err.append(buf.data(), n);
    fclose(e);
  }
  std::filesystem::remove(err_path);
  return r;
}

// run_program of the perclod binary under test.
inline CliResult run_cli(const std::string& args, const std::string& shell_prefix = "") {
  return run_program(PERCLOD_CLI, args, shell_prefix);
}

}  // namespace perclod::test
