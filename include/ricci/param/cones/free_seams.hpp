#pragma once
/// \file
/// Seams that may bend (ParamOptions::seams = SeamMode::Free): the curvature the cut's vertices
/// carry when every seam's two copies keep one length but not one direction.
///
/// The flat metric of the exact mode puts all curvature at the cones, and each seam's two copies
/// differ by a rigid motion. Here the conformal factor u stays one value per vertex (so both
/// copies of a seam edge have one length, e^{(u_i + u_j)/2} times its 3D length), the vertices
/// off the cut stay flat (and a disk boundary keeps what its mode asks), and every vertex of the
/// cut, the cones among them, and of a free boundary takes the curvature that distorts least.
/// The choice is made on the flow linearised at the input metric, K(u) ~ K + L u: u minimises
///     4 u^T M u  +  smoothness / #F  u^T L u
/// subject to (K + L u)_v = K-bar_v at every prescribed vertex v. The first term is the
/// linearised area distortion energy of the tutorial's eq. 9 (E ~ 4 times the area-weighted
/// variance of u; M the vertex areas, and a constant shift of u is free, so the minimiser has
/// mean 0), the second the Dirichlet energy that stands for the angle distortion, weighted as in
/// select_cones. A free vertex's curvature is then K_v + (L u)_v, and the flow realises these
/// curvatures exactly (a target per vertex). The minimiser solves one sparse symmetric
/// quasi-definite system [4M + sL, C^T; C, -delta I], C the prescribed rows of L, in its
/// positive definite form (4M + sL + C^T C / delta) u = C^T b / delta (CHOLMOD's supernodal
/// factorisation).

#include <numbers>
#include <vector>

#include <Eigen/Core>

#include "ricci/flow/flow_problem.hpp"
#include "ricci/flow/target.hpp"
#include "ricci/param/cut/cut_graph.hpp"

namespace ricci {

/// The most curvature a free vertex is given: 1.75 pi, a cone angle of at least pi / 4. (1.5 pi,
/// the cone selection's bound, distorted more where a sharp tip needs a small angle: a cone's tip
/// E 0.245 -> 0.327 over the corpus's meshes with free seams, a tiny bunny 0.092 -> 0.114.)
inline constexpr double kMaxFreeCurvature = 1.75 * std::numbers::pi;

/// Options of free_seam_target.
struct FreeSeamOptions {
  /// Weight of the Dirichlet energy of u (the angle distortion's stand-in) per face, as
  /// ConeSelectionOptions::smoothness.
  double smoothness = 1000;
  /// Weight of the squared curvature of the free vertices per face while select_free_seam_cones
  /// tries cuts (its fast system has no Dirichlet energy; see SeamSystem in free_seams.cpp).
  double selection_smoothness = 3;
};

/// What free_seam_target returns.
struct FreeSeamTarget {
  /// The flow's target: the prescribed curvatures, and on every free vertex the chosen one.
  Target target;
  std::vector<char> free;  ///< #V: vertices of the cut and of a free boundary
  int free_vertices = 0;
  /// Free vertices whose chosen curvature came out above kMaxFreeCurvature and is held there
  /// (the model linearised at needle-shaped triangles can ask for more than 2 pi, which no
  /// metric gives; the excess goes to the other free vertices).
  int capped_vertices = 0;
  Eigen::VectorXd linear_u;       ///< #V: the minimiser u of the linearised flow (mean 0)
  double linear_area_energy = 0;  ///< E of linear_u (eq. 9 with u_f the corners' mean)
  double seconds = 0;
};

/// Chooses the curvature of the cut's vertices (and of a free boundary) for seams that keep
/// their lengths but may bend (see the file comment).
/// \param problem the mesh, its connectivity, input lengths and structure
/// \param cut a cut graph of problem.topology (the cones on it)
/// \param prescribed flat_target of the mesh without cones, boundary as the run asks: its
///        curvature holds at every vertex off the cut whose u it does not fix; the vertices it
///        fixes (a free boundary) are free here
/// \throw InvalidInput when the sizes disagree or the initial metric breaks a triangle inequality
/// \throw SolverError when the system cannot be factorised
FreeSeamTarget free_seam_target(const FlowProblem& problem, const CutGraph& cut,
                                const Target& prescribed, const FreeSeamOptions& options = {});

/// What select_free_seam_cones returns.
struct FreeSeamCones {
  std::vector<int> cones;  ///< the cut's chosen ends, in the order they were added
  CutGraph cut;            ///< the cut through them
  int root = -1;           ///< the root vertex of its homology generators (-1: none, genus 0)
  FreeSeamTarget seams;    ///< the curvature on that cut (seconds: the whole selection)
};

/// Cones for free seams: the cut's ends chosen where they lower the distortion most. Starting
/// from the cut the topology needs (homology generators, all through one root: of the vertices
/// of most negative and most positive curvature, the one whose generators alone distort less;
/// boundaries; a sphere, which has no cut before it has cones, from its vertex of most positive
/// curvature), each round solves the free seams' problem on the
/// current cut with a fast stand-in for the Dirichlet energy (selection_smoothness times the
/// free curvatures' squares, a sparse positive definite system analysed once) and adds the
/// prescribed vertices whose rows carry the largest multipliers (freeing them would lower the
/// objective most), a few rings from the cut and from each other. It stops when `count` cones
/// are placed, or (count 0) when max |u| off the cut is at most max_log_scale, when more cones
/// stop helping (from 64 cones on, twice the cones lowered it by less than 5 %, as the rigid
/// selection's stop) or no vertex is left away from the cut. The final cut's curvature is then
/// chosen with the Dirichlet energy (free_seam_target). \param cut_options the cut's options (its
/// cones are replaced by the chosen ones)
FreeSeamCones select_free_seam_cones(const FlowProblem& problem, const Target& prescribed,
                                     int count, double max_log_scale,
                                     const CutGraphOptions& cut_options,
                                     const FreeSeamOptions& options = {});

}  // namespace ricci
