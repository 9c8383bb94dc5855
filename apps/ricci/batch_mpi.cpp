#include "batch_mpi.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <thread>

#include "param_command.hpp"
#include "ricci/errors.hpp"

#ifdef RICCI_HAVE_MPI
#include "mpi_transport.hpp"
#include "numerics/detail/shared_library.hpp"
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

/// The MPI module's functions (mpi_transport.hpp), loaded by MpiSession's constructor.
const RicciMpiTransport* g_mpi = nullptr;

/// Loads ricci-mpi.so from beside the program (the build tree, a pip package's bin/), else from
/// its install folder (RICCI_MPI_MODULE_FROM_BIN, relative to the program's).
/// \throw InvalidInput naming what is missing
const RicciMpiTransport* load_mpi_transport() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path self = fs::canonical("/proc/self/exe", ec);
  std::vector<fs::path> candidates;
  if (!ec) {
    candidates.push_back(self.parent_path() / "ricci-mpi.so");
    candidates.push_back(self.parent_path() / RICCI_MPI_MODULE_FROM_BIN / "ricci-mpi.so");
  }
  std::string why = ec ? "/proc/self/exe cannot be read" : "not found";
  for (const fs::path& candidate : candidates) {
    if (!fs::exists(candidate, ec)) continue;
    // RTLD_LOCAL: Open MPI's own plugins are loaded by Open MPI itself, with its libraries.
    void* handle = shared_library::open({candidate.c_str()}, RTLD_NOW | RTLD_LOCAL, why);
    if (handle == nullptr) continue;
    RicciMpiTransportEntry entry = nullptr;
    const RicciMpiTransport* transport =
        shared_library::find(handle, "ricci_mpi_transport", entry) ? entry() : nullptr;
    if (transport != nullptr && transport->version == kRicciMpiTransportVersion) return transport;
    why = candidate.string() + " is not this ricci's MPI module";
  }
  throw InvalidInput(
      "ricci batch: started by an MPI launcher, but the MPI module ricci-mpi.so could not be "
      "loaded (" +
      why + "); it is installed beside the program or in " + RICCI_MPI_MODULE_FROM_BIN +
      " from it. Run without mpirun for local workers");
}

void send_text(const std::string& text, int rank, int tag) {
  g_mpi->send(text.data(), static_cast<int>(text.size()), rank, tag);
}

/// A message that has arrived (probed, not yet received).
struct Probed {
  int source = 0, tag = 0, size = 0;
};

/// Waits for a message without spinning a core (Open MPI's blocking calls poll at full speed,
/// which would take a core from the meshes on a small machine). source, tag: -1 for any.
Probed wait_for_message(int source, int tag) {
  Probed p;
  for (;;) {
    // Open MPI 4.1 reports an arrived message on the second probe after its arrival (measured:
    // always 2 calls), so probe twice before each sleep: 2 ms less latency per message.
    for (int probe = 0; probe < 2; ++probe) {
      if (g_mpi->probe(source, tag, &p.source, &p.tag, &p.size)) return p;
    }
    ::usleep(1000);
  }
}

std::string receive_text(const Probed& probed) {
  std::string text(static_cast<std::size_t>(probed.size), '\0');
  g_mpi->receive(text.data(), probed.size, probed.source, probed.tag);
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
    const Probed message = wait_for_message(-1, kResult);
    const std::string line = receive_text(message);
    idle_.push_back(message.source);
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
  if (g_mpi == nullptr) g_mpi = load_mpi_transport();
  g_mpi->init();
  initialised_ = true;
  const int rank = g_mpi->rank();
  ranks_ = g_mpi->size();
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
  g_mpi->finalize();
#endif
}

void MpiSession::stop_workers() {
#ifdef RICCI_HAVE_MPI
  if (workers_stopped_) return;
  workers_stopped_ = true;
  for (int r = 1; r < ranks_; ++r) g_mpi->send(nullptr, 0, r, kStop);
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
  const int rank = g_mpi->rank();
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
    const Probed message = wait_for_message(0, -1);
    const std::string text = receive_text(message);
    if (message.tag == kStop) break;
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
