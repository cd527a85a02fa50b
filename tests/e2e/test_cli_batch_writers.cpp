// Issue 56: one writer per batch output folder. Two runs of one batch at
// once (the second is refused, naming the folder), the shards of a split at
// once (they share it), and a run killed with -9 whose partial folder the
// next run removes even when it skips that model.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "cli_util.h"

namespace batch_writers {

using perclod::test::run_cli;
namespace fs = std::filesystem;

// A batch of the demo building (a few seconds a run: long enough to be
// caught running) on a small display, in temp/perclod-writers-<name>-PID.
struct Batch {
  fs::path root;
  explicit Batch(const std::string& name) : root(perclod::test::fresh_dir("writers-" + name, true)) {
    std::ofstream(root / "display.yaml") << "width: 320\nheight: 256\ndpi: 21.5675\nviewer_distance_m: 0.5\n";
    std::ofstream(root / "batch.yaml") << "out: " << out().string() << "\nup: z\ndistances: [56]\nviews: facades\n"
                                       << "samples: 1\njudge_views: none\ndisplay: display.yaml\n"
                                       << "models:\n  - " << perclod::test::kBuilding << "\n";
  }
  ~Batch() { fs::remove_all(root); }
  std::string config() const { return (root / "batch.yaml").string(); }
  fs::path out() const { return root / "out"; }
  // The partial folders in OUT.
  std::vector<std::string> partials() const {
    std::vector<std::string> r;
    std::error_code ec;
    for (fs::directory_iterator it(out(), ec), end; !ec && it != end; it.increment(ec))
      if (it->path().filename().string().find(".partial-") != std::string::npos)
        r.push_back(it->path().filename().string());
    return r;
  }
};

// `perclod ARGS` as a child of this process (so it can be stopped, killed
// and waited for), stdout and stderr to `log`.
pid_t spawn(const std::string& args, const fs::path& log) {
  const std::string cmd = std::string("exec ") + PERCLOD_CLI + " " + args + " >" + log.string() + " 2>&1";
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

// The exit status of child `pid` (-1 if it did not exit normally).
int wait_exit(pid_t pid) {
  int status = 0;
  if (::waitpid(pid, &status, 0) != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Waits (up to 120 s) until `done` holds or child `pid` has exited.
template <class F>
bool wait_for(pid_t pid, F done) {
  const auto t0 = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(120)) {
    if (done()) return true;
    int status;
    if (::waitpid(pid, &status, WNOHANG) == pid) return done();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return false;
}

std::string text_of(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(CliBatchWriters, ASecondRunOfABatchIsRefusedNamingTheFolder) {
  Batch b("twice");
  const pid_t first = spawn("run " + b.config(), b.root / "first.log");
  ASSERT_TRUE(wait_for(first, [&] { return !b.partials().empty(); })) << text_of(b.root / "first.log");
  auto second = run_cli("run " + b.config());
  EXPECT_EQ(second.exit_code, 1) << second.err;
  EXPECT_NE(second.err.find("perclod: error: " + b.out().string() +
                            ": another perclod command is writing to this directory"),
            std::string::npos)
      << second.err;
  EXPECT_EQ(second.err.find("start:"), std::string::npos) << "the second run did work:\n" << second.err;
  // --force too.
  auto forced = run_cli("run " + b.config() + " --force");
  EXPECT_EQ(forced.exit_code, 1) << forced.err;
  EXPECT_EQ(wait_exit(first), 0) << text_of(b.root / "first.log");
  EXPECT_TRUE(fs::exists(b.out() / "bldg_4018215" / "bldg_4018215_manifest.json"));
  EXPECT_TRUE(b.partials().empty());
  // Once the first has finished, the folder is free again.
  auto again = run_cli("run " + b.config());
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.err.find("up to date, skipped"), std::string::npos) << again.err;
}

TEST(CliBatchWriters, TheShardsOfASplitRunAtOnce) {
  Batch b("shards");
  std::ofstream(b.config(), std::ios::app) << "  - " << perclod::test::kBuilding << "\n";  // a second model
  const pid_t s0 = spawn("run " + b.config() + " --shard 0/2", b.root / "s0.log");
  const pid_t s1 = spawn("run " + b.config() + " --shard 1/2", b.root / "s1.log");
  EXPECT_EQ(wait_exit(s0), 0) << text_of(b.root / "s0.log");
  EXPECT_EQ(wait_exit(s1), 0) << text_of(b.root / "s1.log");
  EXPECT_TRUE(fs::exists(b.out() / "batch_0_of_2.json"));
  EXPECT_TRUE(fs::exists(b.out() / "batch_1_of_2.json"));
  // Two runs of one shard are not.
  const pid_t again = spawn("run " + b.config() + " --shard 0/2 --force", b.root / "again.log");
  ASSERT_TRUE(wait_for(again, [&] { return !b.partials().empty(); })) << text_of(b.root / "again.log");
  auto twice = run_cli("run " + b.config() + " --shard 0/2");
  EXPECT_EQ(twice.exit_code, 1) << twice.err;
  EXPECT_NE(twice.err.find(b.out().string() + ": another perclod command"), std::string::npos) << twice.err;
  EXPECT_EQ(wait_exit(again), 0) << text_of(b.root / "again.log");
}

// The catalogue's case: kill -9 during `run --force` left the partial folder
// beside the model's whole older folder, and reruns skipped the model and
// never removed it.
TEST(CliBatchWriters, ARerunRemovesThePartialFolderOfAKilledRunItSkips) {
  Batch b("killed");
  auto r = run_cli("run " + b.config());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  bool killed = false;
  for (int attempt = 0; attempt < 5 && !killed; ++attempt) {
    const pid_t p = spawn("run " + b.config() + " --force", b.root / "forced.log");
    ASSERT_TRUE(wait_for(p, [&] { return !b.partials().empty(); })) << text_of(b.root / "forced.log");
    ::kill(p, SIGSTOP);  // still partial once stopped (not published meanwhile): kill it there
    killed = !b.partials().empty();
    ::kill(p, killed ? SIGKILL : SIGCONT);
    wait_exit(p);
  }
  ASSERT_TRUE(killed);
  ASSERT_EQ(b.partials().size(), 1u);
  r = run_cli("run " + b.config());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("up to date, skipped"), std::string::npos) << r.err;
  EXPECT_TRUE(b.partials().empty()) << b.partials().front();
  EXPECT_TRUE(fs::exists(b.out() / "bldg_4018215" / "bldg_4018215_manifest.json"));
}

}  // namespace batch_writers
