// The ranks of an `mpirun` as a Cluster (docs/SCALING.md). Built only when CMake finds MPI
// (CAUSTICA_HAVE_MPI); the single-process build has none of it.
#pragma once

#include "core/render/cluster.h"

#include <memory>

namespace caustica {

/// Whether this process was started by mpirun (Open MPI's or another launcher's rank variables),
/// checked before MPI is initialised: a plain `caustica render` never initialises MPI.
bool launched_by_mpirun();

/// Initialises MPI (threads: serialized; the session's worker thread makes the calls) and returns
/// the world as a Cluster; MPI is finalised when it is destroyed. Throws when MPI cannot start.
std::unique_ptr<Cluster> start_mpi_cluster();

/// Ends every rank at once with `code` (after a rank could not take part in a collective).
[[noreturn]] void abort_mpi(int code);

}  // namespace caustica
