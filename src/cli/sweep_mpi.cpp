#include "cli/sweep_mpi.hpp"

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <thread>

#ifdef CUTDYN_WITH_MPI
#include <mpi.h>
#endif

namespace cutdyn::cli {

#ifdef CUTDYN_WITH_MPI
namespace {

constexpr int kResult = 1;  // worker → rank 0: int64 index (−1: ready), then the variant's text
constexpr int kWork = 2;    // rank 0 → worker: int64 index to do (−1: none left)
bool g_started = false;

int env_int(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : fallback;
}

}  // namespace

std::optional<MpiWorld> mpi_start() {
  // Started by a launcher (OpenMPI's mpirun, or a PMI/PMIx launcher such as Slurm's srun).
  if (!std::getenv("OMPI_COMM_WORLD_SIZE") && !std::getenv("PMIX_RANK") && !std::getenv("PMI_RANK"))
    return std::nullopt;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  g_started = true;
  MpiWorld w;
  MPI_Comm_rank(MPI_COMM_WORLD, &w.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &w.size);
  w.local_size = env_int("OMPI_COMM_WORLD_LOCAL_SIZE", w.size);
  return w;
}

void mpi_finish() {
  if (g_started) MPI_Finalize();
  g_started = false;
}

void mpi_share(const MpiWorld& world, const std::vector<std::size_t>& order,
               const std::function<std::string(std::size_t)>& compute,
               const std::function<void(std::size_t, std::string)>& deliver) {
  if (world.rank != 0) {
    long long index = -1;
    std::string text;
    for (;;) {
      std::string message(sizeof index + text.size(), '\0');
      std::memcpy(message.data(), &index, sizeof index);
      std::memcpy(message.data() + sizeof index, text.data(), text.size());
      MPI_Send(message.data(), static_cast<int>(message.size()), MPI_CHAR, 0, kResult,
               MPI_COMM_WORLD);
      MPI_Recv(&index, 1, MPI_LONG_LONG, 0, kWork, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      if (index < 0) return;
      text = compute(static_cast<std::size_t>(index));
    }
  }
  // Rank 0: its main thread answers the workers (and makes every MPI call); a thread of its
  // own computes variants from the same queue.
  std::atomic<std::size_t> next{0};
  const auto take = [&]() -> long long {
    const std::size_t k = next++;
    return k < order.size() ? static_cast<long long>(order[k]) : -1;
  };
  std::exception_ptr failure;
  std::thread local([&] {
    try {
      for (long long i; (i = take()) >= 0;)
        deliver(static_cast<std::size_t>(i), compute(static_cast<std::size_t>(i)));
    } catch (...) {
      failure = std::current_exception();
    }
  });
  int active = world.size - 1;
  while (active > 0) {
    MPI_Status status;
    int arrived = 0;
    for (;;) {  // polled, so that waiting takes no core from the computing threads
      MPI_Iprobe(MPI_ANY_SOURCE, kResult, MPI_COMM_WORLD, &arrived, &status);
      if (arrived) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    int count = 0;
    MPI_Get_count(&status, MPI_CHAR, &count);
    std::string message(static_cast<std::size_t>(count), '\0');
    MPI_Recv(message.data(), count, MPI_CHAR, status.MPI_SOURCE, kResult, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
    long long index = -1;
    std::memcpy(&index, message.data(), sizeof index);
    if (index >= 0) deliver(static_cast<std::size_t>(index), message.substr(sizeof index));
    const long long work = take();
    MPI_Send(&work, 1, MPI_LONG_LONG, status.MPI_SOURCE, kWork, MPI_COMM_WORLD);
    if (work < 0) --active;
  }
  local.join();
  if (failure) std::rethrow_exception(failure);
}

#else  // without MPI: one process

std::optional<MpiWorld> mpi_start() { return std::nullopt; }
void mpi_finish() {}
void mpi_share(const MpiWorld&, const std::vector<std::size_t>&,
               const std::function<std::string(std::size_t)>&,
               const std::function<void(std::size_t, std::string)>&) {
  throw std::logic_error("mpi_share: cutdyn was built without MPI");
}

#endif

}  // namespace cutdyn::cli
