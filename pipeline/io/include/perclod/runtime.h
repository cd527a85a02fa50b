// perclod/runtime.h - what a long job needs from its process: a place to
// report progress, a stopwatch for its timings, and a way to hand freed
// memory back between its stages.
#pragma once

#include <chrono>
#include <functional>
#include <string>

namespace perclod {

// Progress lines for stderr (may be empty).
using Progress = std::function<void(const std::string& message)>;

namespace detail {

using Clock = std::chrono::steady_clock;
inline double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Hands memory freed between a job's stages (ID buffers, the simplifier's
// mesh) back to the system, so the next stage's peak is not stacked on
// free chunks the heap kept (glibc; a no-op elsewhere).
void release_free_memory();

}  // namespace detail
}  // namespace perclod
