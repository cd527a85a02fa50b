// perclod/outputs.h - where every output file goes, and how it gets there.
//
// OutputNames is the one place that builds the file names of the output
// table (docs/usage.md#output-files); every command and the library's orchestration ask it.
// write_atomic is the one way a file is written: to a temporary name in the
// destination folder, renamed into place only once the writer has finished,
// so an interrupted or failed write never leaves a half-written file under
// its final name.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace perclod {

// Files of one model (`stem`, usually the model file's stem) in `dir`.
// Distances print in the shortest form (56 -> "56m", 12.5 -> "12.5m").
struct OutputNames {
  std::string dir;
  std::string stem;

  // <dir>/<stem>_<view>_<d>m<suffix>: renders (".png", "_ids.tif",
  // "_depth.tif"), perception images ("_simulated.png", "_difference.png",
  // "_mask.png") and marking renders ("_marking.png", "_marking_near.png").
  std::string view(const std::string& view, double distance, const std::string& suffix) const;
  std::string labels(double distance) const;        // <dir>/<stem>_labels_<d>m.txt
  std::string label_report(double distance) const;  // <dir>/<stem>_label_<d>m.json
  // <dir>/<stem>_lod_<d>m.<format>, format "obj" or "glb".
  std::string lod(double distance, const std::string& format) const;
  std::string report() const;                       // <dir>/<stem>_report.json
  std::string report_html() const;                  // <dir>/<stem>_report.html (perclod/report_html.h)
  std::string manifest() const;                     // <dir>/<stem>_manifest.json (perclod/model_exports.h)
  std::string tileset() const;                      // <dir>/<stem>_tileset.json
  std::string lods_glb() const;                     // <dir>/<stem>_lods.glb (every LOD, MSFT_lod)
  // <dir>/<stem><suffix>: `perceive` names its images after the input image.
  std::string file(const std::string& suffix) const;
};

// The suffix of every model's tileset (a batch's tileset finds them by it).
constexpr const char* kTilesetSuffix = "_tileset.json";

// A batch's own files in its output folder `out`: the tileset over every
// model (<out>/tileset.json), the index page (<out>/index.html) and shard
// i of n's summary (<out>/batch_<i>_of_<n>.json).
std::string batch_tileset_file(const std::string& out);
std::string batch_index_file(const std::string& out);
std::string batch_summary_file(const std::string& out, int shard, int shards);

// The extension of `path` lower-cased, with its dot: ".obj", "" for none.
std::string lower_extension(const std::string& path);

// A model file's name without its extension, and without the ".city" of
// CityJSON's "name.city.json" (so "name", not "name.city", names its outputs).
std::string model_stem(const std::string& path);

// Names in `dir` after the stem of `input` (the model or image file): out/bldg_...
OutputNames output_names_for(const std::string& dir, const std::string& input);

// "56m", "12.5m": the distance tag of every distance-tagged file name.
std::string distance_tag(double distance);
// Throws std::invalid_argument if two of `distances` have the same distance
// tag (56 and 56.0000001 both print "56m"): their files would overwrite each other.
void check_distinct_tags(const std::vector<double>& distances);

// Calls write(temp) to fill a temporary file beside `path`, then renames it
// to `path`. If `write` throws, or the rename fails, the temporary is removed
// and the error (naming `path`) propagates; an existing `path` is untouched.
// The temporary keeps `path`'s extension (image writers choose the format by
// it) and is unique per process and call: ".tmp-<pid>-<n>-<file name>".
// Before writing, temporaries of `path` left by dead processes are removed.
// `write` must report every failure by throwing: writers whose libraries
// ignore write errors build the bytes in memory and use write_bytes_atomic.
void write_atomic(const std::string& path, const std::function<void(const std::string& temp)>& write);
// write_atomic of a byte string, written with checked write(), fsync() and
// close(): a full disk or any other I/O error throws naming `path`.
void write_bytes_atomic(const std::string& path, std::string_view bytes);
// write_atomic for a text (or any byte string); same as write_bytes_atomic.
void write_text_atomic(const std::string& path, const std::string& text);
// The low-level write under write_bytes_atomic: creates or truncates `file`
// and writes `bytes` with checked write(), fsync() and close(). Errors throw
// std::runtime_error naming `name` (the final path the bytes are meant for)
// and the system's reason, e.g. "out/a.png: cannot write: No space left on device".
void write_bytes(const std::string& file, std::string_view bytes, const std::string& name);
// Installs SIGINT/SIGTERM/SIGHUP handlers that unlink the temporaries of
// write_atomic calls still in flight, then re-raise the signal (the CLI's main).
void remove_temporaries_on_signals();
// Creates a directory (and parents); throws naming it on failure.
void ensure_directory(const std::string& dir);

// The lock file of an output directory (OutputDirectoryLock).
constexpr const char* kLockFile = ".perclod.lock";

// One writer per output directory: creates `dir` and holds an advisory lock
// (flock) on <dir>/<file> (kLockFile unless told) for its lifetime.
// Exclusive, the default: a second perclod command writing to the same
// directory meanwhile is refused with an error naming it, instead of the two
// overwriting each other's finished files. Shared: the shards of one batch
// hold it together, and any exclusive holder is refused (and refuses them).
// The lock file stays when the lock is released: deleting it while held let
// a command that had opened it lock the deleted file while a third locked a
// new one under the same name. A lock file found replaced or deleted after
// locking is opened again.
class OutputDirectoryLock {
 public:
  enum class Mode { Exclusive, Shared };
  explicit OutputDirectoryLock(const std::string& dir, Mode mode = Mode::Exclusive,
                               const std::string& file = kLockFile);
  ~OutputDirectoryLock();
  OutputDirectoryLock(const OutputDirectoryLock&) = delete;
  OutputDirectoryLock& operator=(const OutputDirectoryLock&) = delete;

 private:
  // Opens and locks path_; false when the file was replaced meanwhile.
  bool try_lock(const std::string& dir, Mode mode);
  std::string path_;
  int fd_ = -1;
};

// Whether `name` in a batch's output folder is, or could be, one of the
// batch's own files: index.html, tileset.json, batch_<i>_of_<n>.json, or a
// name starting with '.' (lock files, partial folders, temporaries). A
// model's folder may not take such a name.
bool is_batch_file_name(const std::string& name);

}  // namespace perclod
