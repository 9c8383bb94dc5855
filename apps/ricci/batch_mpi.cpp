#include "batch_mpi.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <thread>

#include "param_command.hpp"
#include "ricci/errors.hpp"

#ifdef RICCI_HAVE_MPI
#include <mpi.h>
#endif

namespace ricci::cli {

namespace {

bool launched_by_mpi() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr ||
         std::getenv("PMI_RANK") != nullptr;
}

#ifdef RICCI_HAVE_MPI
enum Tag : int { kTask = 1, kResult = 2, kStop = 3 };

std::string job_to_json(const BatchJob& job) {
  return nlohmann::json{{"input", job.input},   {"key", job.key},         {"output", job.output},
                        {"report", job.report}, {"options", job.options}, {"bytes", job.bytes}}
      .dump();
}

BatchJob job_from_json(const std::string& text) {
  const nlohmann::json j = nlohmann::json::parse(text);
  BatchJob job;
  job.input = j.at("input").get<std::string>();
  job.key = j.at("key").get<std::string>();
  job.output = j.at("output").get<std::string>();
  job.report = j.at("report").get<std::string>();
  job.options = j.at("options").get<std::vector<std::string>>();
  job.bytes = j.at("bytes").get<std::uintmax_t>();
  return job;
}

void send_text(const std::string& text, int rank, int tag) {
  MPI_Send(text.data(), static_cast<int>(text.size()), MPI_CHAR, rank, tag, MPI_COMM_WORLD);
}

/// Waits for a message without spinning a core (Open MPI's blocking calls poll at full speed,
/// which would take a core from the meshes on a small machine).
MPI_Status wait_for_message(int source, int tag) {
  MPI_Status status;
  int flag = 0;
  for (;;) {
    // Open MPI 4.1 reports an arrived message on the second probe after its arrival (measured:
    // always 2 calls), so probe twice before each sleep: 2 ms less latency per message.
    for (int probe = 0; probe < 2; ++probe) {
      MPI_Iprobe(source, tag, MPI_COMM_WORLD, &flag, &status);
      if (flag) return status;
    }
    ::usleep(1000);
  }
}

std::string receive_text(const MPI_Status& probed) {
  int count = 0;
  MPI_Get_count(&probed, MPI_CHAR, &count);
  std::string text(static_cast<std::size_t>(count), '\0');
  MPI_Recv(text.data(), count, MPI_CHAR, probed.MPI_SOURCE, probed.MPI_TAG, MPI_COMM_WORLD,
           MPI_STATUS_IGNORE);
  return text;
}

/// The other ranks as BatchWorkers: a job goes to an idle rank, a record comes back from any.
class MpiWorkers final : public BatchWorkers {
 public:
  explicit MpiWorkers(int ranks) {
    for (int r = ranks - 1; r >= 1; --r) idle_.push_back(r);
    slots_ = ranks - 1;
  }
  int slots() const override { return slots_; }
  void start(const BatchJob& job) override {
    if (idle_.empty()) throw Error("ricci batch: no idle MPI rank for " + job.key);
    const int rank = idle_.back();
    idle_.pop_back();
    send_text(job_to_json(job), rank, kTask);
  }
  MeshRecord wait() override {
    const MPI_Status status = wait_for_message(MPI_ANY_SOURCE, kResult);
    const std::string line = receive_text(status);
    idle_.push_back(status.MPI_SOURCE);
    return parse_mesh_record(line);
  }

 private:
  std::vector<int> idle_;
  int slots_ = 0;
};
#endif

}  // namespace

MpiSession::MpiSession() {
#ifdef RICCI_HAVE_MPI
  if (!launched_by_mpi()) return;
  MPI_Init(nullptr, nullptr);
  initialised_ = true;
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks_);
  if (ranks_ > 1) role_ = rank == 0 ? MpiRole::Scheduler : MpiRole::Worker;
#else
  if (launched_by_mpi() && std::getenv("RICCI_BATCH_QUIET_MPI") == nullptr) {
    // Each rank would run the whole batch on its own: refuse rather than do the work K times.
    throw InvalidInput(
        "ricci batch: started by an MPI launcher, but this ricci was built without MPI "
        "(install libopenmpi-dev and rebuild); run it without mpirun for local workers");
  }
#endif
}

MpiSession::~MpiSession() {
#ifdef RICCI_HAVE_MPI
  if (!initialised_) return;
  if (role_ == MpiRole::Scheduler) stop_workers();
  MPI_Finalize();
#endif
}

void MpiSession::stop_workers() {
#ifdef RICCI_HAVE_MPI
  if (workers_stopped_) return;
  workers_stopped_ = true;
  for (int r = 1; r < ranks_; ++r) MPI_Send(nullptr, 0, MPI_CHAR, r, kStop, MPI_COMM_WORLD);
#endif
}

BatchResult MpiSession::schedule(const std::vector<BatchJob>& jobs, const std::string& out_dir,
                                 const BatchOptions& options) {
#ifdef RICCI_HAVE_MPI
  MpiWorkers workers(ranks_);
  BatchResult result = run_batch(jobs, out_dir, options, &workers);
  stop_workers();
  return result;
#else
  return run_batch(jobs, out_dir, options);
#endif
}

int MpiSession::work(const BatchOptions& options) {
#ifdef RICCI_HAVE_MPI
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  const std::string label = "rank " + std::to_string(rank) + " on " + host;
  BatchOptions mine = options;
  // One mesh per rank: the cores of this machine shared among its ranks (Open MPI's, PMIx's or
  // Slurm's count of ranks on this node; Slurm's cores per task when it gives them).
  int local_ranks = 1;
  for (const char* name :
       {"OMPI_COMM_WORLD_LOCAL_SIZE", "PMIX_LOCAL_SIZE", "SLURM_NTASKS_PER_NODE"}) {
    if (const char* value = std::getenv(name)) {
      local_ranks = std::max(1, std::atoi(value));
      break;
    }
  }
  mine.jobs = local_ranks;
  if (const char* cpus = std::getenv("SLURM_CPUS_PER_TASK");
      cpus != nullptr && mine.threads_per_job <= 0) {
    mine.threads_per_job = std::max(1, std::atoi(cpus));
  }
  for (;;) {
    const MPI_Status status = wait_for_message(0, MPI_ANY_TAG);
    const std::string text = receive_text(status);
    if (status.MPI_TAG == kStop) break;
    // The scheduler wrote the task: one that does not parse is a bug, not a mesh's failure.
    const BatchJob job = job_from_json(text);
    send_text(to_json_line(run_batch_mesh(job, mine, label)), 0, kResult);
  }
  return kOk;
#else
  (void)options;
  return kOk;
#endif
}

}  // namespace ricci::cli
