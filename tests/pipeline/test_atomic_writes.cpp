// Issue 12 (reliability): a write that fails (full disk, signal) leaves
// nothing under the final name and says which file; temporaries are unique
// per process, and stale ones of dead processes are cleared.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "perclod/export.h"
#include "perclod/image_io.h"
#include "perclod/outputs.h"
#include "test_util.h"

using namespace perclod;
namespace fs = std::filesystem;

namespace {

using test::has;

// Files in `dir` whose names start with ".tmp-".
size_t temporaries_in(const fs::path& dir) {
  size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir)) n += e.path().filename().string().rfind(".tmp-", 0) == 0;
  return n;
}

// Noise does not compress: the PNG is about as large as its pixels.
std::vector<uint8_t> noise(int w, int h) {
  std::vector<uint8_t> px(size_t(w) * h * 3);
  std::mt19937 rng(7);
  for (auto& p : px) p = uint8_t(rng());
  return px;
}

// While alive, files this process writes may not grow beyond `bytes`: the
// write fails (EFBIG) like on a full disk. SIGXFSZ is ignored meanwhile.
struct FileSizeLimit {
  rlimit old{};
  void (*old_handler)(int);
  explicit FileSizeLimit(rlim_t bytes) {
    old_handler = ::signal(SIGXFSZ, SIG_IGN);
    ::getrlimit(RLIMIT_FSIZE, &old);
    rlimit lim = old;
    lim.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &lim);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &old);
    ::signal(SIGXFSZ, old_handler);
  }
};

}  // namespace

// ------------------------------------------------------------ item 1: full disk

TEST(AtomicWrites, WriteBytesToAFullDeviceThrowsNamingTheFile) {
  try {
    write_bytes("/dev/full", "some bytes", "out/model_lod_56m.obj");
    FAIL() << "writing to /dev/full succeeded";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(has(e.what(), "out/model_lod_56m.obj: cannot write")) << e.what();
    EXPECT_TRUE(has(e.what(), "No space left on device")) << e.what();
  }
}

TEST(AtomicWrites, AFullDiskLeavesNoPngGlbOrTextUnderItsFinalName) {
  test::TempDir dir("full-disk");
  const auto px = noise(128, 128);  // ~48 KB of PNG
  const std::string png = dir / "a.png", glb = dir / "a.glb", obj = dir / "a.obj", txt = dir / "a.txt";
  {
    FileSizeLimit limit(4096);
    EXPECT_THROW(write_png(png, 128, 128, 3, px.data()), std::runtime_error);
    // 100 boxes: well over the limit in either format (a GLB holds only the
    // vertices triangles use).
    Scene big = test::box();
    const Scene one = test::box();
    for (int i = 1; i < 100; ++i) {
      const uint32_t base = uint32_t(big.vertex_count());
      for (size_t k = 0; k < one.positions.size(); ++k) big.positions.push_back(one.positions[k] + (k % 3 ? 0.f : 2.f * i));
      for (uint32_t v : one.indices) big.indices.push_back(base + v);
    }
    EXPECT_THROW(export_scene(big, glb), std::runtime_error);
    EXPECT_THROW(export_scene(big, obj), std::runtime_error);
    try {
      write_text_atomic(txt, std::string(10000, 'x'));
      ADD_FAILURE() << "a text beyond the size limit was written";
    } catch (const std::runtime_error& e) {
      EXPECT_TRUE(has(e.what(), txt + ": cannot write")) << e.what();
    }
  }
  for (const auto& p : {png, glb, obj, txt}) EXPECT_FALSE(fs::exists(p)) << p;
  EXPECT_EQ(temporaries_in(dir.path), 0u);
  // The same writes succeed without the limit, and an existing file survives a failed write.
  write_png(png, 128, 128, 3, px.data());
  auto before = fs::file_size(png);
  {
    FileSizeLimit limit(4096);
    EXPECT_THROW(write_png(png, 128, 128, 3, noise(64, 256).data()), std::runtime_error);
  }
  EXPECT_EQ(fs::file_size(png), before);
  EXPECT_EQ(read_rgb8(png).pixels, px);
}

// A real full file system: needs root and a kernel that lets this process mount.
TEST(AtomicWrites, AFullTmpfsLeavesNoPngUnderItsFinalName) {
  test::TempDir dir("tmpfs");
  const std::string mnt = dir / "mnt";
  fs::create_directories(mnt);
  if (::geteuid() != 0 || ::mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=64k") != 0)
    GTEST_SKIP() << "cannot mount a small tmpfs here (" << std::strerror(errno)
                 << "); the RLIMIT_FSIZE test covers the same path";
  const auto px = noise(256, 256);  // ~196 KB of PNG into 64 KB
  const std::string png = mnt + "/a.png";
  std::string message;
  try {
    write_png(png, 256, 256, 3, px.data());
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  EXPECT_FALSE(fs::exists(png));
  size_t temps = temporaries_in(mnt);
  ::umount2(mnt.c_str(), MNT_DETACH);
  EXPECT_TRUE(has(message, png + ": cannot write: No space left on device")) << message;
  EXPECT_EQ(temps, 0u);
}

// ------------------------------------------------------------ item 10: temporaries

TEST(AtomicWrites, StaleTemporariesOfDeadProcessesAreRemoved) {
  test::TempDir dir("stale");
  // A pid far above pid_max of any Linux (4194304) belongs to no process.
  const std::string stale = dir / ".tmp-99999999-0-a.txt";
  const std::string other = dir / ".tmp-99999999-0-b.txt";      // another file's: kept
  const std::string alive = dir / (".tmp-" + std::to_string(::getppid()) + "-3-a.txt");  // a live process: kept
  for (auto& p : {stale, other, alive}) std::ofstream(p) << "half";
  write_text_atomic(dir / "a.txt", "whole\n");
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(other));
  EXPECT_TRUE(fs::exists(alive));
  std::ifstream f(dir / "a.txt");
  std::string line;
  std::getline(f, line);
  EXPECT_EQ(line, "whole");
}

TEST(AtomicWrites, TemporariesAreUniquePerProcessAndCall) {
  test::TempDir dir("unique");
  std::vector<std::string> temps;
  for (int i = 0; i < 2; ++i)
    write_atomic(dir / "x.png", [&](const std::string& tmp) {
      temps.push_back(fs::path(tmp).filename().string());
      std::ofstream(tmp) << i;
    });
  ASSERT_EQ(temps.size(), 2u);
  EXPECT_NE(temps[0], temps[1]);
  const std::string prefix = ".tmp-" + std::to_string(::getpid()) + "-";
  for (auto& t : temps) {
    EXPECT_EQ(t.rfind(prefix, 0), 0u) << t;
    EXPECT_EQ(fs::path(t).extension(), ".png") << t;  // writers choose the format by it
  }
}

// A process killed by SIGTERM while writing leaves no temporary behind.
TEST(AtomicWrites, ASignalDuringAWriteRemovesTheTemporary) {
  test::TempDir dir("signal");
  const std::string path = dir / "a.png";
  pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    remove_temporaries_on_signals();
    write_atomic(path, [](const std::string& tmp) {
      std::ofstream(tmp) << "half";
      ::raise(SIGTERM);  // the handler unlinks the temporary, then the default action ends us
      ::pause();
    });
    ::_exit(0);  // not reached
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(temporaries_in(dir.path), 0u);
}

namespace {

// A second writer of one output directory is refused while the first holds
// it; the lock file stays when it is released.
TEST(OutputDirectoryLock, OneWriterPerDirectory) {
  test::TempDir dir("lock");
  const std::string out = dir / "out";
  {
    OutputDirectoryLock first(out);
    EXPECT_TRUE(fs::exists(out + "/.perclod.lock"));
    try {
      OutputDirectoryLock second(out);
      ADD_FAILURE() << "two locks on one directory";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("another perclod command"), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).rfind(out, 0), 0u) << e.what();
    }
    OutputDirectoryLock elsewhere(dir / "other");  // other directories are free
  }
  EXPECT_TRUE(fs::exists(out + "/.perclod.lock"));
  OutputDirectoryLock again(out);  // released: the next command may write
}

// Issue 56, item 7: the lock file was deleted while held, so a command that
// had opened it before could lock the deleted file while a third command
// locked a new one: two writers. Now the file stays, and whoever opened it
// earlier contends for the same lock as the next command.
TEST(OutputDirectoryLock, TheLockFileIsNotDeletedWhileHeld) {
  test::TempDir dir("lock-kept");
  const std::string out = dir / "out", file = out + "/.perclod.lock";
  int early = -1;
  {
    OutputDirectoryLock first(out);
    early = ::open(file.c_str(), O_RDWR | O_CLOEXEC);  // a second command, between its open and its flock
    ASSERT_GE(early, 0);
    EXPECT_NE(::flock(early, LOCK_EX | LOCK_NB), 0);  // refused while the first holds it
  }
  OutputDirectoryLock third(out);  // the next command, after the first finished
  EXPECT_NE(::flock(early, LOCK_EX | LOCK_NB), 0) << "the early opener and the third command both hold a lock";
  ::close(early);
  EXPECT_TRUE(fs::exists(file));
}

// The shards of one batch share the output folder's lock; a command that
// wants it alone is refused while they hold it, and they while it does.
TEST(OutputDirectoryLock, SharedHoldersExcludeAnExclusiveOne) {
  test::TempDir dir("lock-shared");
  const std::string out = dir / "out";
  using Mode = OutputDirectoryLock::Mode;
  {
    OutputDirectoryLock a(out, Mode::Shared), b(out, Mode::Shared);
    EXPECT_THROW(OutputDirectoryLock c(out), std::runtime_error);
    OutputDirectoryLock shard(out, Mode::Exclusive, ".perclod-shard-0-of-2.lock");
    EXPECT_THROW(OutputDirectoryLock again(out, Mode::Exclusive, ".perclod-shard-0-of-2.lock"), std::runtime_error);
  }
  OutputDirectoryLock alone(out);
  EXPECT_THROW(OutputDirectoryLock shared(out, Mode::Shared), std::runtime_error);
}

TEST(OutputNames, BatchFileNamesAreRecognised) {
  for (const char* name : {"index.html", "tileset.json", "batch_0_of_1.json", "batch_12_of_345.json", ".hidden",
                           ".perclod.lock", ".a.partial-host-12"})
    EXPECT_TRUE(is_batch_file_name(name)) << name;
  for (const char* name : {"index", "index.html.2", "tileset", "batch_0_of_1", "batch_x_of_1.json",
                           "batch_0_of_.json", "batch_0_of_1.json.old", "bldg_4018215", "a.b"})
    EXPECT_FALSE(is_batch_file_name(name)) << name;
}

}  // namespace

// ImageWriter encodes on its own thread: the files are write_png's bytes, a
// failure comes back from finish() naming the file, the images queued after
// it are still written, and a queue smaller than one image still moves.
TEST(AtomicWrites, ImageWriterWritesWhatWritePngWritesAndReportsAFailure) {
  test::TempDir dir("image-writer");
  auto bytes = [](const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const auto a = noise(128, 128), b = noise(64, 256);
  write_png(dir / "direct.png", 128, 128, 3, a.data());
  {
    ImageWriter w(1000);  // smaller than any of these images
    w.png(dir / "a.png", 128, 128, 3, a);
    w.png(dir / "missing/x.png", 64, 256, 3, b);  // no such folder
    w.png(dir / "b.png", 64, 256, 3, b);
    try {
      w.finish();
      ADD_FAILURE() << "a failed write was not reported";
    } catch (const std::runtime_error& e) {
      EXPECT_TRUE(has(e.what(), dir / "missing/x.png")) << e.what();
    }
    w.finish();  // the failure was reported once
    w.png(dir / "c.png", 128, 128, 3, a);
  }  // the destructor waits for c.png
  EXPECT_EQ(bytes(dir / "a.png"), bytes(dir / "direct.png"));
  EXPECT_EQ(read_rgb8(dir / "b.png").pixels, b);
  EXPECT_EQ(bytes(dir / "c.png"), bytes(dir / "direct.png"));
  EXPECT_FALSE(fs::exists(dir / "missing"));
  EXPECT_EQ(temporaries_in(dir.path), 0u);
}
