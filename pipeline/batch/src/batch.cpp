// `perclod run` on a batch: one folder per model, built aside and published
// whole, skipped when up to date, sharded, several models at a time within a
// memory budget; the batch's tileset, summary and index page.
#include "perclod/batch.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <stdio.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "perclod/export.h"
#include "perclod/load.h"
#include "perclod/outputs.h"
#include "perclod/batch_summary.h"
#include "perclod/progress_text.h"
#include "perclod/report_html.h"
#include "perclod/report_json.h"
#include "perclod/run_model.h"
#include "batch_util.h"
#include "perclod/lods.h"
#include "perclod/model_exports.h"
#include "perclod/runtime.h"

namespace perclod {
using detail::Clock;
using detail::since;
using namespace detail;
namespace fs = std::filesystem;

std::pair<int, int> parse_shard(const std::string& spec) {
  const size_t slash = spec.find('/');
  auto num = [&](const std::string& s) {
    size_t used = 0;
    long v = -1;
    try {
      v = std::stol(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != s.size() || s.empty()) throw std::invalid_argument("--shard must be i/n (e.g. 0/3), got '" + spec + "'");
    return v;
  };
  if (slash == std::string::npos) throw std::invalid_argument("--shard must be i/n (e.g. 0/3), got '" + spec + "'");
  const long i = num(spec.substr(0, slash)), n = num(spec.substr(slash + 1));
  if (n < 1 || n > 1000000 || i < 0 || i >= n)
    throw std::invalid_argument("--shard i/n needs 0 <= i < n, got '" + spec + "'");
  return {int(i), int(n)};
}

std::vector<size_t> shard_indices(size_t count, int shard, int shards) {
  std::vector<size_t> r;
  for (size_t i = size_t(shard); i < count; i += size_t(shards)) r.push_back(i);
  return r;
}

// An upper bound for `perclod run` with the default settings, fitted to its
// peak resident memory on generated facades and the demo building, with
// about 10% to spare (docs/usage.md#models-at-a-time;
// BENCHMARKS.md#the-memory-estimate).
double estimate_memory_mb(const std::string& model_file) {
  std::error_code ec;
  const double mb = double(fs::file_size(model_file, ec)) / (1024.0 * 1024.0);
  return 500.0 + 10.0 * (ec ? 0.0 : mb);
}

namespace {

struct Slot {
  size_t index = 0;  // in config.models
  ModelOutcome result;
};

// A JSON file (a manifest, a tileset, a summary), or null when it is missing
// or unreadable.
nlohmann::json read_json_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) return nullptr;
  try {
    return nlohmann::json::parse(in);
  } catch (const std::exception&) {
    return nullptr;
  }
}

// Per LOD of a manifest: distance, total triangles, worst figures.
std::vector<LodSummary> summary_lods(const nlohmann::json& manifest) {
  std::vector<LodSummary> r;
  const nlohmann::json lods = manifest.is_object() ? manifest.value("lods", nlohmann::json::array()) : nlohmann::json();
  if (lods.is_array())
    for (const auto& l : lods) {
      if (!l.is_object()) continue;
      LodSummary s;
      s.distance = l.value("distance", 0.0);
      s.triangles = l.value("triangles", nlohmann::json::object()).value("total", size_t(0));
      const nlohmann::json w = l.value("fidelity", nlohmann::json::object()).value("worst", nlohmann::json::object());
      if (w.is_object() && !w.empty())
        s.worst = WorstFigures{w.value("changed_fraction", 0.0), w.value("ssim_covered", 1.0),
                               w.value("silhouette_mismatch", 0.0)};
      r.push_back(s);
    }
  return r;
}

std::string manifest_path(const std::string& dir, const BatchConfig& c) {
  return output_names_for(dir, c.model).manifest();
}

std::string host_name() {
  char buf[256] = {0};
  if (::gethostname(buf, sizeof buf - 1) != 0 || !buf[0]) return "host";
  std::string h = buf;
  for (auto& ch : h)
    if (ch == '/' || ch == '-' || ch == '.') ch = '_';
  return h;
}

// The folder a model is built in: .<name>.partial-<host>-<pid> beside its
// final folder (the host too: several machines may share `out`).
std::string partial_dir(const std::string& out, const std::string& name) {
  return (fs::path(out) / ("." + name + ".partial-" + host_name() + "-" + std::to_string(::getpid()))).string();
}

// The pid in a partial folder's name .<name>.partial-<host>-<pid>[.old] of
// this host, 0 when `f` is not one (or of another host), and only of model
// `name` unless that is empty.
long partial_owner(const std::string& f, const std::string& name) {
  const std::string tag = ".partial-" + host_name() + "-";
  const size_t at = f.rfind(tag);
  if (f.empty() || f[0] != '.' || at == std::string::npos || at < 1) return 0;
  if (!name.empty() && f.compare(0, at, "." + name) != 0) return 0;
  try {
    return std::stol(f.substr(at + tag.size()));
  } catch (const std::exception&) {
    return 0;
  }
}

// Partial folders of model `name` (every model's when empty) left by
// processes of this host that are gone, or by an earlier process with this
// one's pid (another host's are left alone: its process cannot be asked).
void remove_stale_partials(const std::string& out, const std::string& name) {
  std::error_code ec;
  for (fs::directory_iterator it(out, ec), end; !ec && it != end; it.increment(ec)) {
    const long pid = partial_owner(it->path().filename().string(), name);
    if (pid == 0) continue;
    std::error_code rm;
    if (pid == long(::getpid()) ? name.empty() : !process_alive(pid)) fs::remove_all(it->path(), rm);
  }
}

// Moves the finished `partial` folder to `final_dir`; an older complete
// folder there is swapped out in one step (renameat2 RENAME_EXCHANGE) and
// removed, so `final_dir` always holds one whole set of outputs.
void publish(const std::string& partial, const std::string& final_dir) {
  std::error_code ec;
  if (!fs::exists(final_dir, ec)) {
    fs::rename(partial, final_dir, ec);
    if (ec) throw std::runtime_error(final_dir + ": cannot move the finished outputs into place: " + ec.message());
    return;
  }
  if (::renameat2(AT_FDCWD, partial.c_str(), AT_FDCWD, final_dir.c_str(), RENAME_EXCHANGE) == 0) {
    fs::remove_all(partial, ec);  // now the old outputs
    return;
  }
  if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP)
    throw std::runtime_error(final_dir + ": cannot replace the old outputs: " + std::strerror(errno));
  // Filesystems without an exchanging rename (NFS, some FUSE): the old folder
  // goes aside, the new one in; only between the two is `final_dir` absent.
  const std::string aside = partial + ".old";
  fs::rename(final_dir, aside, ec);
  if (ec) throw std::runtime_error(final_dir + ": cannot move the old outputs aside: " + ec.message());
  fs::rename(partial, final_dir, ec);
  if (ec) {
    std::error_code back;
    fs::rename(aside, final_dir, back);
    throw std::runtime_error(final_dir + ": cannot move the finished outputs into place: " + ec.message());
  }
  fs::remove_all(aside, ec);
}

// Holds an exclusive flock on a file for its lifetime (waits for it).
class FileLock {
 public:
  explicit FileLock(const std::string& path) : fd_(::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666)) {
    if (fd_ >= 0) ::flock(fd_, LOCK_EX);
  }
  ~FileLock() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

}  // namespace

// <out>/tileset.json: one child per complete model folder (external tilesets).
void write_batch_tileset(const std::string& out) {
  nlohmann::json children = nlohmann::json::array();
  double error = 0;
  std::error_code ec;
  std::vector<fs::path> dirs;
  for (fs::directory_iterator it(out, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_directory(ec) && it->path().filename().string()[0] != '.') dirs.push_back(it->path());
  std::sort(dirs.begin(), dirs.end());
  for (const auto& d : dirs)
    for (const auto& f : fs::directory_iterator(d, ec)) {
      const std::string name = f.path().filename().string();
      const size_t n = std::strlen(kTilesetSuffix);
      if (name.size() < n || name.compare(name.size() - n, n, kTilesetSuffix) != 0) continue;
      nlohmann::json t = read_json_file(f.path().string());
      if (!t.is_object() || !t.contains("root")) continue;
      nlohmann::json root = t["root"];
      nlohmann::json child = {{"boundingVolume", root["boundingVolume"]},
                              {"geometricError", t["geometricError"]},
                              {"content", {{"uri", (d.filename() / name).string()}}}};
      // The model's own transform (crs_origin) applies inside its tileset;
      // the child's volume must be in this tileset's frame, so place a
      // transformed model by a sphere around its box.
      if (root.contains("transform")) {
        const auto& m = root["transform"];
        const auto& b = root["boundingVolume"]["box"];
        double c[3], r = 0;
        for (int a = 0; a < 3; ++a)
          c[a] = m[a].get<double>() * b[0].get<double>() + m[4 + a].get<double>() * b[1].get<double>() +
                 m[8 + a].get<double>() * b[2].get<double>() + m[12 + a].get<double>();
        for (int k = 0; k < 3; ++k) {
          double l = 0;
          for (int a = 0; a < 3; ++a) l += b[3 + 3 * k + a].get<double>() * b[3 + 3 * k + a].get<double>();
          r += std::sqrt(l);
        }
        child["boundingVolume"] = {{"sphere", {c[0], c[1], c[2], r}}};
      }
      error = std::max(error, t["geometricError"].get<double>());
      children.push_back(child);
    }
  if (children.empty()) return;
  // The root's volume: a sphere around every child's box or sphere.
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (const auto& ch : children) {
    const auto& v = ch["boundingVolume"];
    double c[3], r;
    if (v.contains("sphere")) {
      for (int a = 0; a < 3; ++a) c[a] = v["sphere"][a].get<double>();
      r = v["sphere"][3].get<double>();
    } else {
      const auto& b = v["box"];
      for (int a = 0; a < 3; ++a) c[a] = b[a].get<double>();
      r = std::abs(b[3].get<double>()) + std::abs(b[7].get<double>()) + std::abs(b[11].get<double>());
    }
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a] - r), hi[a] = std::max(hi[a], c[a] + r);
  }
  double c[3], r = 0;
  for (int a = 0; a < 3; ++a) c[a] = 0.5 * (lo[a] + hi[a]), r += 0.25 * (hi[a] - lo[a]) * (hi[a] - lo[a]);
  // The root's error: at least each child's and the batch's diameter. The
  // tileset's own error (that of drawing nothing) is the same, never below
  // the root's, as in a model's tileset.
  const double root_error = std::max(error, 2 * std::sqrt(r));
  nlohmann::json ts = {{"asset", {{"version", "1.1"}, {"generator", std::string("perclod ") + perclod_version()}}},
                       {"geometricError", root_error},
                       {"root", {{"boundingVolume", {{"sphere", {c[0], c[1], c[2], std::sqrt(r)}}}},
                                 {"geometricError", root_error},
                                 {"refine", "ADD"},
                                 {"children", children}}}};
  write_text_atomic(batch_tileset_file(out), ts.dump(2) + "\n");
}

namespace {

// <out>/index.html from every shard's summary batch_<i>_of_<n>.json on disk
// (the shards of one split: each lists its own models).
void write_batch_index(const std::string& out, int shards) {
  nlohmann::json all = {{"models", nlohmann::json::array()}, {"done", 0}, {"skipped", 0}, {"failed", 0}, {"seconds", 0.0}};
  for (int i = 0; i < shards; ++i) {
    const nlohmann::json s = read_json_file(batch_summary_file(out, i, shards));
    if (!s.is_object()) continue;
    for (const auto& m : s["models"]) all["models"].push_back(m);
    for (const char* k : {"done", "skipped", "failed"}) all[k] = all[k].get<int>() + s.value(k, 0);
    all["seconds"] = std::max(all["seconds"].get<double>(), s.value("seconds", 0.0));
  }
  write_text_atomic(batch_index_file(out), batch_index_html(all));
}

// What every model of this batch process shares and nothing changes: the
// config, the options, the log, when the batch started, how many models this
// shard runs and the memory budget (MB, 0 or less: none).
struct BatchRun {
  const ConfigFile& config;
  const BatchOptions& options;
  const std::function<void(const std::string&)>& log;
  bool eta;
  Clock::time_point t0;
  size_t total;
  double budget;
};

// The shared progress of the models, under mu: their slots, their weights
// (file MB + 1, for the time left), the next in the queue and the memory the
// running ones are estimated to take.
struct BatchProgress {
  std::vector<Slot> slots;
  std::vector<double> weight;
  double weight_total = 0;
  std::mutex mu;
  std::condition_variable cv;
  size_t next = 0;
  double running_mb = 0, weight_done = 0;
};

// A slot and a weight for each of this shard's models (mine: their indices in config.models).
void init_progress(const ConfigFile& config, const std::vector<size_t>& mine, BatchProgress& p) {
  const size_t total = mine.size();
  p.slots.resize(total);
  p.weight.resize(total);
  for (size_t i = 0; i < total; ++i) {
    p.slots[i].index = mine[i];
    std::error_code ec;
    const auto bytes = fs::file_size(config.models[mine[i]].config.model, ec);
    p.weight[i] = 1.0 + (ec ? 0.0 : double(bytes) / 1e6);  // MB + 1
    p.weight_total += p.weight[i];
  }
}

// Logs a line about model i, with the time left when asked for.
void say(const BatchRun& b, BatchProgress& p, size_t i, const std::string& what) {
  const ModelEntry& m = b.config.models[p.slots[i].index];
  std::lock_guard<std::mutex> g(p.mu);
  double left = -1;
  if (b.eta && p.weight_done > 0) left = since(b.t0) / p.weight_done * (p.weight_total - p.weight_done);
  if (b.log) b.log(batch_line(i, b.total, m.name, what, left));
}

// Whether the manifest old (null when none) is of a complete run of this
// version on the same model and settings.
bool up_to_date(const nlohmann::json& old, const ModelRun& run) {
  const auto field = [&](const char* part) {  // old[part]["hash"], "" when absent
    return old.is_object() ? old.value(part, nlohmann::json::object()).value("hash", std::string()) : std::string();
  };
  return old.is_object() && old.value("complete", false) && old.value("perclod_version", "") == perclod_version() &&
         field("model") == run.input_hash && field("config") == run.settings_hash;
}

// Runs model i (started at t) in a partial folder and publishes it as
// final_dir, filling its result r (the partial folder is removed on failure).
void build_model(const BatchRun& b, BatchProgress& p, size_t i, const ModelRun& run, const std::string& final_dir,
                 Clock::time_point t, ModelOutcome& r) {
  const ModelEntry& m = b.config.models[p.slots[i].index];
  const BatchConfig& c = m.config;
  remove_stale_partials(b.config.out, m.name);
  const std::string partial = partial_dir(b.config.out, m.name);
  std::error_code ec;
  fs::remove_all(partial, ec);
  say(b, p, i, "start: " + c.model);
  try {
    // Messages name the folder the files will be in once complete.
    auto moved = [&](std::string s) {
      for (size_t at; (at = s.find(partial + "/")) != std::string::npos;)
        s.replace(at, partial.size(), final_dir);
      return s;
    };
    nlohmann::json man;
    TextProgress progress([&](const std::string& s) { say(b, p, i, moved(s)); });
    const ModelReport report = run_model(c, run, partial, &progress, &man);
    // Paths in the report and outputs become relative to the model's folder.
    nlohmann::json rel = model_report_json(report);
    relocate(rel, partial + "/", "");
    const OutputNames names = output_names_for(partial, c.model);
    write_text_atomic(names.report(), rel.dump(2) + "\n");
    write_manifest(names, man);  // its checksum of the report, now rewritten
    // run_model's lock is released, and no other command writes to this
    // process's partial folder: its lock file is not part of the outputs.
    fs::remove(fs::path(partial) / kLockFile, ec);
    publish(partial, final_dir);
    r.status = ModelStatus::Done;
    r.lods = summary_lods(man);
    const nlohmann::json& files = man.at("files");
    if (files.contains("report_html")) r.report_html = m.name + "/" + files["report_html"].get<std::string>();
    for (const std::string& w : report.lods.warnings) r.warnings.push_back("[" + m.name + "] " + moved(w));
    r.over_limits = report.lods.over_limits;
  } catch (...) {
    fs::remove_all(partial, ec);
    throw;
  }
  say(b, p, i, "done in " + format_seconds(since(t)) + ": " + final_dir);
}

// Model i: skipped when its folder is up to date, else built; its result
// (done, skipped or failed) goes into its slot.
void run_one_model(const BatchRun& b, BatchProgress& p, size_t i) {
  const ModelEntry& m = b.config.models[p.slots[i].index];
  const BatchConfig& c = m.config;
  const std::string final_dir = (fs::path(b.config.out) / m.name).string();
  const auto t = Clock::now();
  ModelOutcome r;
  r.name = m.name, r.model = c.model, r.dir = m.name;
  try {
    const ModelRun run = model_run(m, b.config.path);
    const nlohmann::json old = read_json_file(manifest_path(final_dir, c));
    if (!b.options.force && up_to_date(old, run)) {
      r.status = ModelStatus::Skipped;
      r.lods = summary_lods(old);
      const nlohmann::json files = old.value("files", nlohmann::json::object());
      if (files.contains("report_html")) r.report_html = m.name + "/" + files["report_html"].get<std::string>();
      say(b, p, i, "up to date, skipped (--force redoes it)");
    } else {
      build_model(b, p, i, run, final_dir, t, r);
    }
  } catch (const std::exception& e) {
    r.status = ModelStatus::Failed;
    r.error = e.what();
    say(b, p, i, std::string("FAILED: ") + e.what());
  }
  r.seconds = since(t);
  std::lock_guard<std::mutex> g(p.mu);
  p.slots[i].result = r;
  p.weight_done += p.weight[i];
}

// A worker: takes models in list order; a model starts only while its memory
// estimate fits beside the running ones (the first always starts).
void run_worker(const BatchRun& b, BatchProgress& p) {
  for (;;) {
    size_t i;
    double need;
    {
      std::unique_lock<std::mutex> lk(p.mu);
      if (p.next >= b.total) return;
      i = p.next;
      const BatchConfig& c = b.config.models[p.slots[i].index].config;
      need = c.memory_mb > 0 ? c.memory_mb : estimate_memory_mb(c.model);
      p.cv.wait(lk, [&] { return p.running_mb == 0 || b.budget <= 0 || p.running_mb + need <= b.budget; });
      if (i != p.next) continue;  // another worker took it meanwhile
      ++p.next;
      p.running_mb += need;
    }
    run_one_model(b, p, i);
    {
      std::lock_guard<std::mutex> g(p.mu);
      p.running_mb -= need;
    }
    p.cv.notify_all();
  }
}

// One writer per batch output folder, held for the whole batch: a batch
// run holds OUT's lock exclusively, so a second run of it (or any other
// command writing to OUT) is refused naming the folder. The shards of a
// split share it, each holding its own shard's lock alone.
struct BatchLock {
  BatchLock(const std::string& out, const BatchOptions& o) {
    if (o.shards == 1) {
      all.emplace(out);
      return;
    }
    all.emplace(out, OutputDirectoryLock::Mode::Shared);
    mine.emplace(out, OutputDirectoryLock::Mode::Exclusive,
                 ".perclod-shard-" + std::to_string(o.shard) + "-of-" + std::to_string(o.shards) + ".lock");
  }
  std::optional<OutputDirectoryLock> all, mine;
};

// This shard's summary (every model's result and the counts by status),
// written as <out>/batch_<shard>_of_<shards>.json.
BatchSummary write_shard_summary(const ConfigFile& config, const BatchOptions& options, std::vector<Slot>& slots,
                                 Clock::time_point t0) {
  BatchSummary summary;
  summary.shard = std::to_string(options.shard) + "/" + std::to_string(options.shards);
  summary.config = config.path;
  summary.perclod_version = perclod_version();
  for (Slot& s : slots) {
    const ModelStatus st = s.result.status;
    (st == ModelStatus::Done ? summary.done : st == ModelStatus::Skipped ? summary.skipped : summary.failed) += 1;
    summary.models.push_back(std::move(s.result));
  }
  summary.seconds = since(t0);
  write_text_atomic(batch_summary_file(config.out, options.shard, options.shards),
                    batch_summary_json(summary).dump(2) + "\n");
  return summary;
}

}  // namespace

BatchSummary run_batch(const ConfigFile& config, const BatchOptions& options,
                         const std::function<void(const std::string&)>& log, bool eta) {
  const auto t0 = Clock::now();
  const BatchLock lock(config.out, options);
  remove_stale_partials(config.out, "");  // whether or not their models run again
  const std::vector<size_t> mine = shard_indices(config.models.size(), options.shard, options.shards);
  const int jobs = std::max(1, options.jobs > 0 ? options.jobs : config.jobs);
  const double budget = options.memory_budget_mb >= 0 ? options.memory_budget_mb : config.memory_budget_mb;
  const size_t total = mine.size();
  const BatchRun b{config, options, log, eta, t0, total, budget};
  BatchProgress p;
  init_progress(config, mine, p);

  std::vector<std::thread> pool;
  for (int k = 0; k < std::min<int>(jobs, int(total)); ++k) pool.emplace_back([&] { run_worker(b, p); });
  for (auto& th : pool) th.join();

  BatchSummary summary = write_shard_summary(config, options, p.slots, t0);
  {
    // Shards finishing together take turns, so the last one's scan sees every
    // folder and summary published before it.
    FileLock lock((fs::path(config.out) / ".batch.lock").string());
    write_batch_tileset(config.out);
    write_batch_index(config.out, options.shards);
  }
  return summary;
}

}  // namespace perclod
