// Independent jobs spread over threads (OpenMP, dynamic schedule): lobe speeds, sweep points.
#pragma once

#include <functional>

namespace cutdyn {

/// The most threads a job may be asked for (the command line's --threads, the Python
/// module's threads=): more would only exhaust the machine.
inline constexpr int kMaxThreads = 1024;

/// Calls job(i) for i = 0 .. count − 1 on `threads` threads (0: all cores). `progress(done,
/// count)`, if set, is called from one thread at a time as jobs complete. The first exception
/// thrown by a job (or by `progress`: a caller's way to stop) is rethrown after the loop; the
/// jobs not yet started when it was thrown are skipped. `threads` outside 0 to kMaxThreads
/// throws InvalidInput naming "threads" before any job runs.
void parallel_for(int count, int threads, const std::function<void(int)>& job,
                  const std::function<void(int done, int total)>& progress = {});

}  // namespace cutdyn
