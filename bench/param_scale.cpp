// `parameterize` end to end on large meshes against one CHOLMOD analyse + factorise of the same
// mesh's cotangent Laplacian (docs/performance.md).
//
// Cases: generated disks of about 10k, 100k and 1M faces (the target: at 1M faces the
// whole parameterisation in at most 1.5 times the baseline, peak memory under 1.5 GB), and for
// context a 1M-face torus and a 200k-face genus-2 closed surface (automatic cones).
//
// Every measurement runs in a forked child of a small parent, so that runs do not share a heap
// or caches: the child generates the mesh, resets its peak resident set size (/proc/self/
// clear_refs), then runs either parameterize (the parameterisation's peak memory is the child's
// VmHWM afterwards: the input mesh and the process image are included, nothing else) or the
// baseline (Laplacian assembled outside the clock; analyse + factorise timed). Two baselines:
// ricci's SparseCholesky (OpenBLAS pinned to one thread, as in the flow, for results independent
// of the thread count) and CHOLMOD called directly with its defaults (BLAS on every thread the
// process has): the ratio to the second is the one a user comparing with a bare solve sees.
// Param and baseline runs alternate, `--runs` times each, and the table shows medians.
//
//   build/bench/ricci_param_scale                       # every case, 3 runs each
//   build/bench/ricci_param_scale --runs 5 --cases disk1m
//   build/bench/ricci_param_scale --cases disk10k,disk100k --runs 1
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#ifdef RICCI_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

#include "bench_support.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/metric/angles.hpp"
#include "ricci/metric/hessian.hpp"
#include "ricci/metric/lengths.hpp"
#include "ricci/metric/scheme.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"
#include "ricci/param/parameterize.hpp"

namespace {

using ricci::bench::Clock;
using ricci::bench::peak_memory_mb;
using ricci::bench::reset_peak_memory;
using ricci::bench::seconds_since;

struct Case {
  std::string name;
  std::string description;
  std::function<ricci::Mesh()> make;
};

std::vector<Case> all_cases() {
  return {
      {"disk10k", "disk, make_disk(41, 0.5)", [] { return ricci::make_disk(41, 0.5); }},
      {"disk100k", "disk, make_disk(129, 0.5)", [] { return ricci::make_disk(129, 0.5); }},
      {"disk1m", "disk, make_disk(408, 0.5)", [] { return ricci::make_disk(408, 0.5); }},
      {"torus1m", "torus, make_torus(1000, 500)", [] { return ricci::make_torus(1000, 500); }},
      {"genus2", "genus 2, make_closed_surface(2, 225), automatic cones",
       [] { return ricci::make_closed_surface(2, 225); }},
  };
}

/// What one parameterisation run reports back to the parent (plain doubles through a pipe).
struct ParamRun {
  double faces = 0, seconds = 0, peak_mb = 0, converged = 0;
  double cones = 0, flow = 0, cut = 0, development = 0, layout = 0, atlas = 0, distortion = 0;
  double flow_setup = 0, assembly = 0, analysis = 0, factorization = 0, solve = 0;
  double line_search = 0, flow_internal = 0, iterations = 0, num_cones = 0;
  double max_error = 0, length_error = 0, flipped_faces = 0;
};

struct BaselineRun {
  double seconds = 0, analyse = 0, peak_mb = 0;
};

ParamRun run_param(const Case& c) {
  const ricci::Mesh mesh = c.make();
  reset_peak_memory();
  const auto t0 = Clock::now();
  const ricci::MeshParamResult r = ricci::parameterize(mesh, ricci::ParamOptions{});
  ParamRun run;
  run.seconds = seconds_since(t0);
  run.peak_mb = peak_memory_mb();
  run.faces = mesh.num_faces();
  run.converged = r.converged;
  run.cones = r.timings.cones;
  run.flow = r.timings.flow;
  run.cut = r.timings.cut;
  run.development = r.timings.development;
  run.layout = r.timings.layout;
  run.atlas = r.timings.atlas;
  run.distortion = r.timings.distortion;
  for (const ricci::ComponentFlow& cf : r.flow.components) {
    const ricci::FlowTimings& t = cf.flow.timings;
    run.flow_setup += t.setup;
    run.assembly += t.assembly;
    run.analysis += t.analysis;
    run.factorization += t.factorization;
    run.solve += t.solve;
    run.line_search += t.line_search;
    run.flow_internal += t.total;
    run.iterations += cf.flow.iterations;
  }
  run.num_cones = static_cast<double>(r.cones.size());
  run.max_error = r.flow.max_error;
  run.length_error = r.layout.max_length_relative_error;
  run.flipped_faces = r.distortion.flipped_faces;
  return run;
}

/// direct: CHOLMOD through Eigen's wrapper with its defaults, BLAS threads as the process has
/// them; else ricci's SparseCholesky, which pins OpenBLAS to one thread for results that do not
/// depend on the thread count (the flow's own factorisations run that way).
BaselineRun run_baseline(const Case& c, bool direct) {
  const ricci::Mesh mesh = c.make();
  // The cotangent Laplacian of the input (positive semi-definite on any mesh: the P1 stiffness
  // matrix), made definite by a large diagonal penalty on the boundary (or on vertex 0 of a
  // closed surface), as a Dirichlet problem is.
  const ricci::Topology t = ricci::build_topology(mesh.triangles, mesh.num_vertices());
  const Eigen::VectorXd l = ricci::input_edge_lengths(mesh, t);
  const ricci::ConformalStructure s = ricci::make_conformal_structure(t, l, {}).structure;
  ricci::CornerAngles angles;
  ricci::corner_angles(t, l, angles);
  Eigen::VectorXd hw, ew;
  ricci::halfedge_weights(t, s, s.initial_u, l, angles, hw);
  ricci::edge_weights(t, hw, ew);
  Eigen::SparseMatrix<double> L = ricci::curvature_hessian(t, ew);
  bool any_boundary = false;
  for (int v = 0; v < t.num_vertices; ++v) {
    if (t.is_boundary_vertex[v]) {
      L.coeffRef(v, v) += 1e10;
      any_boundary = true;
    }
  }
  if (!any_boundary) L.coeffRef(0, 0) += 1e10;
  L.makeCompressed();
  reset_peak_memory();
  BaselineRun run;
  if (direct) {
#ifdef RICCI_HAVE_CHOLMOD
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> cholesky;
    const auto t0 = Clock::now();
    cholesky.analyzePattern(L);
    run.analyse = seconds_since(t0);
    cholesky.factorize(L);
    run.seconds = seconds_since(t0);
#endif
  } else {
    ricci::SparseCholesky cholesky;
    const auto t0 = Clock::now();
    cholesky.analyze(L);
    run.analyse = seconds_since(t0);
    cholesky.factorize(L);
    run.seconds = seconds_since(t0);
  }
  run.peak_mb = peak_memory_mb();
  return run;
}

/// Runs `work` in a forked child and returns what it wrote.
template <typename Result>
Result in_child(const std::function<Result()>& work) {
  int fds[2];
  if (pipe(fds) != 0) {
    std::perror("pipe");
    std::exit(1);
  }
  const pid_t pid = fork();
  if (pid < 0) {
    std::perror("fork");
    std::exit(1);
  }
  if (pid == 0) {
    close(fds[0]);
    Result r = work();
    const ssize_t written = write(fds[1], &r, sizeof r);
    close(fds[1]);
    _exit(written == static_cast<ssize_t>(sizeof r) ? 0 : 1);
  }
  close(fds[1]);
  Result r{};
  std::size_t got = 0;
  while (got < sizeof r) {
    const ssize_t n = read(fds[0], reinterpret_cast<char*>(&r) + got, sizeof r - got);
    if (n <= 0) break;
    got += static_cast<std::size_t>(n);
  }
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (got != sizeof r || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::fprintf(stderr, "child failed (status %d)\n", status);
    std::exit(1);
  }
  return r;
}

double median(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  const std::size_t n = x.size();
  return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}

template <typename Run>
double median_of(const std::vector<Run>& runs, double Run::*field) {
  std::vector<double> x;
  for (const Run& r : runs) x.push_back(r.*field);
  return median(x);
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 3;
  std::vector<std::string> wanted;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--runs" && i + 1 < argc) {
      runs = std::max(1, std::atoi(argv[++i]));
    } else if (arg == "--cases" && i + 1 < argc) {
      std::string list = argv[++i];
      for (std::size_t start = 0; start <= list.size();) {
        const std::size_t comma = std::min(list.find(',', start), list.size());
        if (comma > start) wanted.push_back(list.substr(start, comma - start));
        start = comma + 1;
      }
    } else {
      std::fprintf(stderr, "usage: %s [--runs N] [--cases disk10k,disk100k,...]\n", argv[0]);
      return 2;
    }
  }
  std::vector<Case> cases;
  for (const Case& c : all_cases()) {
    if (wanted.empty() || std::find(wanted.begin(), wanted.end(), c.name) != wanted.end())
      cases.push_back(c);
  }
  if (cases.empty()) {
    std::fprintf(stderr, "no such case\n");
    return 2;
  }

  struct Row {
    Case c;
    std::vector<ParamRun> param;
    std::vector<BaselineRun> baseline, direct;
  };
  std::vector<Row> rows;
  for (const Case& c : cases) {
    Row row{c, {}, {}, {}};
    for (int i = 0; i < runs; ++i) {
      row.param.push_back(in_child<ParamRun>([&] { return run_param(c); }));
      row.baseline.push_back(in_child<BaselineRun>([&] { return run_baseline(c, false); }));
#ifdef RICCI_HAVE_CHOLMOD
      row.direct.push_back(in_child<BaselineRun>([&] { return run_baseline(c, true); }));
#endif
      const ParamRun& p = row.param.back();
      std::fprintf(stderr,
                   "%s run %d: param %.3f s (%s, flow error %.1e, length error %.1e, %g flipped) "
                   "peak %.0f MB; baseline %.3f s (analyse %.3f)\n",
                   c.name.c_str(), i + 1, p.seconds, p.converged ? "converged" : "NOT converged",
                   p.max_error, p.length_error, p.flipped_faces, p.peak_mb,
                   row.baseline.back().seconds, row.baseline.back().analyse);
    }
    rows.push_back(std::move(row));
  }

  std::printf(
      "Medians of %d runs (param and baselines alternating, each in a fresh forked child; "
      "peak = the child's VmHWM from just before parameterize, input mesh included; "
      "baseline: SparseCholesky, BLAS on one thread as in the flow; direct: CHOLMOD's "
      "defaults, BLAS on every thread).\n\n",
      runs);
  std::printf(
      "| case | faces | param s | baseline s | ratio | CHOLMOD direct s | ratio to direct | "
      "param peak MB | cones | flow | cut | development | layout | atlas | distortion |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const Row& r : rows) {
    const double p = median_of(r.param, &ParamRun::seconds);
    const double b = median_of(r.baseline, &BaselineRun::seconds);
    const double d = r.direct.empty() ? 0.0 : median_of(r.direct, &BaselineRun::seconds);
    std::printf(
        "| %s | %.0f | %.3f | %.3f | %.2f | %.3f | %.2f | %.0f | %.3f | %.3f | %.3f | %.3f | "
        "%.3f | %.3f | %.3f |\n",
        r.c.name.c_str(), r.param.front().faces, p, b, p / b, d, d > 0 ? p / d : 0.0,
        median_of(r.param, &ParamRun::peak_mb), median_of(r.param, &ParamRun::cones),
        median_of(r.param, &ParamRun::flow), median_of(r.param, &ParamRun::cut),
        median_of(r.param, &ParamRun::development), median_of(r.param, &ParamRun::layout),
        median_of(r.param, &ParamRun::atlas), median_of(r.param, &ParamRun::distortion));
  }
  std::printf(
      "\nInside the flow stage (medians, seconds; 'outside' = flow stage minus the "
      "RicciFlow totals: structure, target, checks, gathering):\n\n");
  std::printf(
      "| case | cones | iterations | setup | assembly | analysis | factorisation | solve | "
      "line search | RicciFlow total | outside | baseline analyse |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const Row& r : rows) {
    std::printf(
        "| %s | %.0f | %.0f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f |\n",
        r.c.name.c_str(), median_of(r.param, &ParamRun::num_cones),
        median_of(r.param, &ParamRun::iterations), median_of(r.param, &ParamRun::flow_setup),
        median_of(r.param, &ParamRun::assembly), median_of(r.param, &ParamRun::analysis),
        median_of(r.param, &ParamRun::factorization), median_of(r.param, &ParamRun::solve),
        median_of(r.param, &ParamRun::line_search), median_of(r.param, &ParamRun::flow_internal),
        median_of(r.param, &ParamRun::flow) - median_of(r.param, &ParamRun::flow_internal),
        median_of(r.baseline, &BaselineRun::analyse));
  }
  return 0;
}
