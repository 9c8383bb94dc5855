// Newton Ricci flow on generated tori of about 10k, 100k and 1M faces, flattened to 1e-10.
// Prints per size: set-up time, Newton iterations, time per phase, total, peak memory, and, in
// the same run, one analyse-plus-factorise of the same Hessian alone with the ratio of the two
// (the target: flow total <= 3 x that, peak memory <= 2 GB at 1M faces).
//
//   build/bench/ricci_flow_benchmark                      # all sizes
//   build/bench/ricci_flow_benchmark --benchmark_filter=/1000/   # the 1M-face torus only
//
// BM_HyperbolicUniformization: the whole hyperbolic pipeline (flow to zero curvature, long
// double refinement, cut, disk layout, Fuchsian group) on generated genus-2 surfaces of about
// 17k, 100k and 1M faces.
#include <benchmark/benchmark.h>

#include <chrono>
#include <fstream>
#include <string>

#include "bench_support.hpp"
#include "ricci/flow/mesh_flow.hpp"
#include "ricci/hyperbolic/hyperbolic_param.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/metric/hessian.hpp"
#include "ricci/metric/lengths.hpp"
#include "ricci/numerics/sparse_cholesky.hpp"

namespace {

using ricci::bench::Clock;
using ricci::bench::peak_memory_mb;
using ricci::bench::reset_peak_memory;
using ricci::bench::seconds_since;

void BM_FlatTorusNewton(benchmark::State& state) {
  const int major = static_cast<int>(state.range(0));
  const int minor = major / 2;
  for (auto _ : state) {
    reset_peak_memory();
    auto t0 = Clock::now();
    const ricci::Mesh mesh = ricci::make_torus(major, minor);
    const double generate = seconds_since(t0);

    ricci::MeshFlowOptions options;  // Thurston packing fitted to the torus, flat target
    const ricci::MeshFlowResult r = ricci::flow_mesh(mesh, options);
    const double peak = peak_memory_mb();
    if (!r.converged) state.SkipWithError(r.components[0].flow.message.c_str());
    const ricci::FlowResult& f = r.components[0].flow;

    // The same Hessian (at the solution, gauge vertex removed) analysed and factorised alone.
    Eigen::VectorXd hw, ew;
    ricci::CornerAngles angles;
    Eigen::VectorXd lengths;
    const auto& s = r.structure.structure;
    ricci::edge_lengths(r.intrinsic.topology(), s, r.u, lengths);
    ricci::corner_angles(r.intrinsic.topology(), lengths, angles);
    ricci::halfedge_weights(r.intrinsic.topology(), s, r.u, lengths, angles, hw);
    ricci::edge_weights(r.intrinsic.topology(), hw, ew);
    const Eigen::SparseMatrix<double> L = ricci::curvature_hessian(r.intrinsic.topology(), ew);
    const Eigen::Index n = L.rows() - 1;
    const Eigen::SparseMatrix<double> H = L.bottomRightCorner(n, n);
    ricci::SparseCholesky alone;
    t0 = Clock::now();
    alone.analyze(H);
    alone.factorize(H);
    const double analyse_factorise = seconds_since(t0);

    const double flow_seconds = r.total_seconds;
    state.SetIterationTime(flow_seconds);
    state.counters["faces"] = mesh.num_faces();
    state.counters["generate_s"] = generate;
    state.counters["setup_s"] = r.setup_seconds + f.timings.setup;
    state.counters["newton_iterations"] = f.iterations;
    state.counters["assembly_s"] = f.timings.assembly;
    state.counters["analysis_s"] = f.timings.analysis;
    state.counters["factorization_s"] = f.timings.factorization;
    state.counters["solve_s"] = f.timings.solve;
    state.counters["line_search_s"] = f.timings.line_search;
    state.counters["flow_total_s"] = flow_seconds;
    state.counters["analyse_factorise_alone_s"] = analyse_factorise;
    state.counters["ratio"] = flow_seconds / analyse_factorise;
    state.counters["peak_MB"] = peak;
    state.counters["final_error"] = r.max_error;
  }
}

BENCHMARK(BM_FlatTorusNewton)
    ->ArgName("major")
    ->Arg(100)   // 10,000 faces
    ->Arg(316)   // 99,856 faces
    ->Arg(1000)  // 1,000,000 faces
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);

void BM_HyperbolicUniformization(benchmark::State& state) {
  const int resolution = static_cast<int>(state.range(0));
  for (auto _ : state) {
    reset_peak_memory();
    const ricci::Mesh mesh = ricci::make_closed_surface(2, resolution);
    const ricci::HyperbolicParamResult r = ricci::parameterize_hyperbolic(mesh);
    const double peak = peak_memory_mb();
    if (!r.converged) state.SkipWithError(r.message.c_str());
    const ricci::FlowResult& f = r.flow.components[0].flow;
    state.SetIterationTime(r.seconds);
    state.counters["faces"] = mesh.num_faces();
    state.counters["newton_iterations"] = f.iterations;
    state.counters["flow_s"] = f.timings.total;
    state.counters["total_s"] = r.seconds;
    state.counters["refined_error"] = r.refinement.max_error_after;
    state.counters["cuts_tried"] = r.cut_candidates_tried;
    state.counters["relation_residual"] = r.group.relation_residual;
    state.counters["length_error"] = r.layout.max_length_relative_error;
    state.counters["peak_MB"] = peak;
  }
}

BENCHMARK(BM_HyperbolicUniformization)
    ->ArgName("resolution")
    ->Arg(64)   // 16,900 faces
    ->Arg(160)  // 102,400 faces
    ->Arg(500)  // about 1M faces
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
