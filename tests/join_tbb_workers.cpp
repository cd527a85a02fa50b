// Linked into every test program: oneTBB's worker threads are waited for
// before LeakSanitizer's exit-time check, which stops every thread and can
// crash on one that is still ending (pipeline/cli/main.cpp says when it
// did). The sanitizer installs its check before any static object is made,
// so this object's destructor runs first.
#include <new>

#include <oneapi/tbb/global_control.h>

namespace {

struct JoinWorkerThreads {
  tbb::task_scheduler_handle handle{tbb::attach{}};
  ~JoinWorkerThreads() { tbb::finalize(handle, std::nothrow); }
} join_workers;

}  // namespace
