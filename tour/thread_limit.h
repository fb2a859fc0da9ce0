#pragma once
// The thread policy (thread_count, tour/tour.h) applied to TBB for as long as a job runs: the one
// way every tour job limits its threads, so that --threads and SLURM_CPUS_PER_TASK mean the same
// in `tour`, `render`, `path` and `evaluate`.
#include <tbb/global_control.h>

#include <cstddef>

#include "tour/tour.h"

namespace meshtour {

/// Limits TBB to thread_count(requested, quiet) threads until destroyed (RAII: the limit ends with
/// the job, also when it throws). Results never depend on the count.
class ThreadLimit {
public:
  ThreadLimit(int requested, bool quiet)
      : threads_(thread_count(requested, quiet)), limit_(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads_)) {}
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

  /// The number of threads the job may use.
  int threads() const { return threads_; }

private:
  int threads_;
  tbb::global_control limit_;
};

}  // namespace meshtour
