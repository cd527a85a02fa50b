// Output file names and atomic writes (perclod/outputs.h).
#include "perclod/outputs.h"

#include <cctype>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace perclod {
namespace fs = std::filesystem;

std::string distance_tag(double d) {
  std::ostringstream ss;
  ss << d << "m";
  return ss.str();
}

void check_distinct_tags(const std::vector<double>& distances) {
  for (size_t i = 0; i < distances.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (distance_tag(distances[i]) == distance_tag(distances[j])) {
        char a[32], b[32];
        std::string sa(a, std::to_chars(a, a + sizeof a, distances[j]).ptr);
        std::string sb(b, std::to_chars(b, b + sizeof b, distances[i]).ptr);
        throw std::invalid_argument(
            (sa == sb ? "distance " + sa + " is given twice"
                      : "distances " + sa + " and " + sb + " both name their files '" + distance_tag(distances[i]) +
                            "' and would overwrite each other") +
            "; give distinct distances");
      }
}

std::string model_stem(const std::string& path) {
  std::string stem = fs::path(path).stem().string();
  const std::string city = ".city";
  if (lower_extension(path) == ".json" && stem.size() > city.size()) {
    std::string tail = stem.substr(stem.size() - city.size());
    for (auto& ch : tail) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    if (tail == city) stem.resize(stem.size() - city.size());
  }
  return stem;
}

OutputNames output_names_for(const std::string& dir, const std::string& input) { return {dir, model_stem(input)}; }

std::string OutputNames::file(const std::string& suffix) const { return dir + "/" + stem + suffix; }

std::string OutputNames::view(const std::string& view, double d, const std::string& suffix) const {
  return file("_" + view + "_" + distance_tag(d) + suffix);
}

std::string OutputNames::labels(double d) const { return file("_labels_" + distance_tag(d) + ".txt"); }

std::string OutputNames::label_report(double d) const { return file("_label_" + distance_tag(d) + ".json"); }

std::string OutputNames::lod(double d, const std::string& format) const {
  return file("_lod_" + distance_tag(d) + "." + format);
}

std::string OutputNames::report() const { return file("_report.json"); }
std::string OutputNames::manifest() const { return file("_manifest.json"); }
std::string OutputNames::tileset() const { return file(kTilesetSuffix); }
std::string OutputNames::lods_glb() const { return file("_lods.glb"); }

std::string batch_tileset_file(const std::string& out) { return (std::filesystem::path(out) / "tileset.json").string(); }
std::string batch_index_file(const std::string& out) { return (std::filesystem::path(out) / "index.html").string(); }
std::string batch_summary_file(const std::string& out, int shard, int shards) {
  return (std::filesystem::path(out) / ("batch_" + std::to_string(shard) + "_of_" + std::to_string(shards) + ".json"))
      .string();
}

std::string lower_extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (auto& ch : e) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  return e;
}

std::string OutputNames::report_html() const { return file("_report.html"); }

namespace {

// Temporaries of write_atomic calls in flight, for the signal handler: a
// fixed table (no allocation, no locks) of 0 free / 1 being filled / 2 ready.
constexpr int kTempSlots = 64;
struct TempSlot {
  std::atomic<int> state{0};
  char path[4096];
};
TempSlot g_temps[kTempSlots];

int register_temp(const std::string& tmp) {
  if (tmp.size() >= sizeof(TempSlot::path)) return -1;
  for (int i = 0; i < kTempSlots; ++i) {
    int expected = 0;
    if (!g_temps[i].state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(g_temps[i].path, tmp.c_str(), tmp.size() + 1);
    g_temps[i].state.store(2);
    return i;
  }
  return -1;  // more writes in flight than slots: this one is not cleaned on a signal
}

void unregister_temp(int slot) {
  if (slot >= 0) g_temps[slot].state.store(0);
}

extern "C" void remove_temps_and_reraise(int sig) {
  for (auto& t : g_temps)
    if (t.state.load() == 2) ::unlink(t.path);  // async-signal-safe
  ::signal(sig, SIG_DFL);
  ::raise(sig);  // delivered when the handler returns: the default action ends the process
}

// ".tmp-<pid>-<n>-<name>": the pid of a temporary's writer, or 0 if `file` is
// not a temporary of `name`.
long temp_owner(const std::string& file, const std::string& name) {
  const std::string prefix = ".tmp-";
  if (file.size() < prefix.size() + name.size() + 4 || file.compare(0, prefix.size(), prefix) != 0 ||
      file.compare(file.size() - name.size() - 1, std::string::npos, "-" + name) != 0)
    return 0;
  const char* b = file.data() + prefix.size();
  const char* e = file.data() + file.size() - name.size() - 1;
  long pid = 0;
  auto r = std::from_chars(b, e, pid);
  if (r.ec != std::errc() || r.ptr == e || *r.ptr != '-' || pid <= 0) return 0;
  unsigned long n = 0;
  auto r2 = std::from_chars(r.ptr + 1, e, n);
  if (r2.ec != std::errc() || r2.ptr != e) return 0;
  return pid;
}

// Removes temporaries of `p` whose writing process no longer exists.
void remove_stale_temps(const fs::path& p) {
  std::error_code ec;
  const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  const std::string name = p.filename().string();
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string f = it->path().filename().string();
    long pid = temp_owner(f, name);
    if (pid == 0 || pid == long(::getpid())) continue;
    if (::kill(pid_t(pid), 0) == -1 && errno == ESRCH) {
      std::error_code rm;
      fs::remove(it->path(), rm);
    }
  }
}

}  // namespace

void write_atomic(const std::string& path, const std::function<void(const std::string& temp)>& write) {
  static std::atomic<unsigned long> counter{0};
  fs::path p(path);
  remove_stale_temps(p);
  const std::string tmp = (p.parent_path() / (".tmp-" + std::to_string(::getpid()) + "-" +
                                               std::to_string(counter++) + "-" + p.filename().string()))
                              .string();
  const int slot = register_temp(tmp);
  std::error_code ec;
  try {
    write(tmp);
  } catch (...) {
    fs::remove(tmp, ec);
    unregister_temp(slot);
    throw;
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code rm;
    fs::remove(tmp, rm);
    unregister_temp(slot);
    throw std::runtime_error(path + ": cannot move the finished file into place: " + ec.message());
  }
  unregister_temp(slot);
}

void write_bytes(const std::string& file, std::string_view bytes, const std::string& name) {
  auto fail = [&](const char* what, int err) {
    return std::runtime_error(name + ": " + what + ": " + std::strerror(err) +
                              (err == ENOSPC || err == EDQUOT || err == EFBIG ? " (disk full?)" : ""));
  };
  int fd;
  do fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  while (fd < 0 && errno == EINTR);
  if (fd < 0) throw fail("cannot open for writing", errno);
  const char* d = bytes.data();
  size_t left = bytes.size();
  while (left > 0) {
    ssize_t n = ::write(fd, d, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      int err = n < 0 ? errno : ENOSPC;
      ::close(fd);
      throw fail("cannot write", err);
    }
    d += n;
    left -= size_t(n);
  }
  // fsync reports write-back errors of file systems that defer them; special
  // files that cannot sync (EINVAL) have nothing to flush.
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) {
    int err = errno;
    ::close(fd);
    throw fail("cannot write", err);
  }
  if (::close(fd) != 0 && errno != EINTR) throw fail("cannot write", errno);
}

void write_bytes_atomic(const std::string& path, std::string_view bytes) {
  write_atomic(path, [&](const std::string& tmp) { write_bytes(tmp, bytes, path); });
}

void write_text_atomic(const std::string& path, const std::string& text) { write_bytes_atomic(path, text); }

void remove_temporaries_on_signals() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction sa {};
    sa.sa_handler = remove_temps_and_reraise;
    sigemptyset(&sa.sa_mask);
    ::sigaction(sig, &sa, nullptr);
  }
}

void ensure_directory(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw std::runtime_error(dir + ": cannot create directory");
}

OutputDirectoryLock::OutputDirectoryLock(const std::string& dir, Mode mode, const std::string& file)
    : path_(dir + "/" + file) {
  ensure_directory(dir);
  for (int attempt = 0; !try_lock(dir, mode); ++attempt)
    if (attempt == 100) throw std::runtime_error(path_ + ": cannot lock: the file keeps being replaced");
}

bool OutputDirectoryLock::try_lock(const std::string& dir, Mode mode) {
  fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error(path_ + ": cannot create the output lock: " + std::strerror(errno));
  if (::flock(fd_, (mode == Mode::Shared ? LOCK_SH : LOCK_EX) | LOCK_NB) != 0) {
    const int e = errno;
    ::close(fd_);
    fd_ = -1;
    if (e == EWOULDBLOCK)
      throw std::runtime_error(dir + ": another perclod command is writing to this directory (it holds " +
                               path_ + "); wait for it or choose another output directory");
    throw std::runtime_error(path_ + ": cannot lock: " + std::strerror(e));
  }
  // Locked; but if the name now holds another file (or none), whoever locks
  // that one would not see this lock: start again on the file there now.
  struct stat held {}, named {};
  if (::fstat(fd_, &held) == 0 && ::stat(path_.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
      held.st_ino == named.st_ino)
    return true;
  ::close(fd_);
  fd_ = -1;
  return false;
}

OutputDirectoryLock::~OutputDirectoryLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock; the file stays (see perclod/outputs.h)
}

bool is_batch_file_name(const std::string& name) {
  if (name.empty() || name[0] == '.' || name == "index.html" || name == "tileset.json") return true;
  // batch_<i>_of_<n>.json
  const auto digits = [&](size_t& at) {
    const size_t from = at;
    while (at < name.size() && std::isdigit(static_cast<unsigned char>(name[at]))) ++at;
    return at > from;
  };
  size_t at = 0;
  const auto word = [&](const char* w) {
    const size_t n = std::strlen(w);
    if (name.compare(at, n, w) != 0) return false;
    at += n;
    return true;
  };
  return word("batch_") && digits(at) && word("_of_") && digits(at) && word(".json") && at == name.size();
}

}  // namespace perclod
