// `cutdyn sweep` under MPI (docs/scaling.md): the variants shared dynamically between the
// ranks of `mpirun -n N`, rank 0 writing the file. Built with OpenMPI when CMake finds it
// (CUTDYN_WITH_MPI); without it, or when not started by mpirun, a sweep is one process.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace cutdyn::cli {

struct MpiWorld {
  int rank = 0, size = 1;
  int local_size = 1;  // ranks on this machine (their threads share its cores)
};

/// Under mpirun (a launcher's rank variables set): initialises MPI and returns the world;
/// otherwise nullopt, and MPI is not touched.
std::optional<MpiWorld> mpi_start();
/// Ends MPI if mpi_start began it.
void mpi_finish();

/// Hands out `order` (variant indices, in the order to start them) one at a time to whichever
/// rank asks next; every rank runs `compute(i)`. On rank 0, `deliver(i, text)` receives every
/// variant's text — its own and the other ranks' — from any thread; the other ranks return
/// when no variant is left.
void mpi_share(const MpiWorld& world, const std::vector<std::size_t>& order,
               const std::function<std::string(std::size_t)>& compute,
               const std::function<void(std::size_t, std::string)>& deliver);

}  // namespace cutdyn::cli
