// parallel_for (cutdyn/core/detail/parallel.hpp): every job once, progress from one thread at a
// time (each count once), and the first exception rethrown with the jobs not yet started skipped
// (how a caller stops a long sweep: the Python module's Ctrl-C).
#include "cutdyn/core/detail/parallel.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

namespace cutdyn {
namespace {

TEST(ParallelFor, RunsEveryJobOnceAndReportsProgress) {
  std::vector<std::atomic<int>> runs(200);
  std::vector<int> seen(201, 0);  // each count 1 … 200 reported once (not always in order)
  parallel_for(
      200, 2, [&](int i) { ++runs[static_cast<std::size_t>(i)]; },
      [&](int done, int total) {
        EXPECT_EQ(total, 200);
        ++seen.at(static_cast<std::size_t>(done));  // unsynchronised: would race
      });
  for (const auto& r : runs) EXPECT_EQ(r.load(), 1);
  for (int d = 1; d <= 200; ++d) EXPECT_EQ(seen[static_cast<std::size_t>(d)], 1) << d;
}

TEST(ParallelFor, AnExceptionStopsTheJobsNotYetStarted) {
  // One thread: job 3 throws; jobs 4 … 999 never run, and the exception reaches the caller.
  std::atomic<int> ran{0};
  EXPECT_THROW(parallel_for(1000, 1,
                            [&](int i) {
                              ++ran;
                              if (i == 3) throw std::runtime_error("stop");
                            }),
               std::runtime_error);
  EXPECT_EQ(ran.load(), 4);
  // Thrown from the progress report (a caller cancelling): the same.
  ran = 0;
  EXPECT_THROW(parallel_for(
                   1000, 1, [&](int) { ++ran; },
                   [](int done, int) {
                     if (done == 10) throw std::runtime_error("cancel");
                   }),
               std::runtime_error);
  EXPECT_EQ(ran.load(), 10);
}

}  // namespace
}  // namespace cutdyn
