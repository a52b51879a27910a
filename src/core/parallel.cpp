#include "cutdyn/core/detail/parallel.hpp"

#include <omp.h>

#include <atomic>
#include <exception>
#include <mutex>
#include <string>

#include "cutdyn/core/error.hpp"

namespace cutdyn {

void parallel_for(int count, int threads, const std::function<void(int)>& job,
                  const std::function<void(int, int)>& progress) {
  if (threads < 0 || threads > kMaxThreads)
    throw InvalidInput({"threads = " + std::to_string(threads) + ": must be 0 (all cores) to " +
                        std::to_string(kMaxThreads)},
                       "request");
  std::exception_ptr error;
  std::mutex mutex;
  std::atomic<int> done{0};
  std::atomic<bool> failed{false};  // once a job has thrown, the rest are skipped
  const int n_threads = threads > 0 ? threads : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic, 1) num_threads(n_threads)
  for (int i = 0; i < count; ++i) {
    if (failed.load(std::memory_order_relaxed)) continue;
    try {
      job(i);
      const int finished = ++done;
      if (progress) {
        std::lock_guard<std::mutex> lock(mutex);
        progress(finished, count);
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex);
      if (!error) error = std::current_exception();
      failed = true;
    }
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace cutdyn
