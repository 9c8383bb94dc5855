#pragma once
/// \file
/// `ricci batch` under `mpirun -n K`: rank 0 schedules (largest meshes first, to whichever rank is
/// free) and alone writes the results log; ranks 1..K-1 each run one mesh at a time in a child
/// process, exactly as a local worker does. Built when CMake finds MPI (RICCI_HAVE_MPI);
/// otherwise, and when not launched by an MPI launcher, the batch runs locally.

#include <string>
#include <vector>

#include "ricci/batch/batch.hpp"

namespace ricci::cli {

enum class MpiRole {
  Local,      ///< not under an MPI launcher, or a single rank
  Scheduler,  ///< rank 0 of several
  Worker,     ///< another rank
};

/// MPI for the lifetime of a batch: initialised when the process was started by an MPI launcher
/// (Open MPI's OMPI_COMM_WORLD_SIZE or PMIx's PMIX_RANK in the environment), finalised at the
/// end. A scheduler that ends before its workers were stopped (an error) stops them.
class MpiSession {
 public:
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  MpiRole role() const { return role_; }
  int ranks() const { return ranks_; }

  /// Rank 0: run_batch with the other ranks as workers; stops them at the end.
  BatchResult schedule(const std::vector<BatchJob>& jobs, const std::string& out_dir,
                       const BatchOptions& options);
  /// The other ranks: run the meshes rank 0 sends until it says stop. Returns an exit code.
  int work(const BatchOptions& options);

 private:
  void stop_workers();
  MpiRole role_ = MpiRole::Local;
  int ranks_ = 1;
  bool initialised_ = false;
  bool workers_stopped_ = false;
};

}  // namespace ricci::cli
