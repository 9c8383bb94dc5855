/// \file
/// parameterize itself: a mesh of one component goes to the pipeline (one_component.cpp) and is
/// kept when it passes its own checks; a mesh of several, or one whose exact map failed them, is
/// parameterized component by component (each routed on its own), gathered into the whole mesh
/// and its charts packed into one atlas.

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <complex>
#include <deque>
#include <iomanip>
#include <numbers>
#include <numeric>
#include <sstream>
#include <string>

#include <Eigen/Geometry>

#include "numerics/detail/bucket_sort.hpp"
#include "param/atlas/detail/charts.hpp"
#include "param/atlas/detail/unfolding.hpp"
#include "param/detail/one_component.hpp"
#include "ricci/errors.hpp"
#include "ricci/mesh/components.hpp"
#include "ricci/mesh/polygons.hpp"
#include "ricci/metric/angles.hpp"
#include "ricci/metric/curvature.hpp"
#include "ricci/metric/scheme.hpp"
#include "ricci/numerics/timer.hpp"
#include "ricci/param/layout/polygon_fans.hpp"
#include "ricci/param/parameterize.hpp"

namespace ricci {
namespace {

using param_detail::charts_result;
using param_detail::ChartsLayout;
using param_detail::develop_patches;
using param_detail::embedded_pieces;
using param_detail::lay_out_charts;
using param_detail::PatchLayout;
using param_detail::split_at_charts;
using param_detail::unfolded_result;

using param_detail::Points;

/// A component whose flow layout maps some face with sigma_max / sigma_min above this is
/// unfolded instead when its own shape lays out in one chart. Conformal layouts stay near 1
/// (1.1 to 2 on the shared meshes); tens to 1e5 come from tiny closed parts given the few cones
/// their topology needs (the repaired dragon's needle tetrahedra).
constexpr double kUnfoldAbove = 10;

/// One component on its way into the atlas.
struct Piece {
  ComponentParam info;
  Triangles cut_triangles;      ///< #F of info.param.mesh by 3: its cut-mesh vertices
  std::vector<int> cut_vertex;  ///< per cut-mesh vertex: vertex of info.param.mesh
  Points layout;                ///< per cut-mesh vertex, scaled by info.area_scale
  std::vector<int> face_chart;  ///< #F of info.param.mesh: its own chart (one chart: empty)
  int num_charts = 1;
  std::vector<char> cut_edges;  ///< Patches: #E of its mesh, the edges between patches' faces
  int exact_flipped = 0;        ///< faces the exact map drew flipped, before untangling
};

/// The rigid motion z -> a z + b of a chart, seen after the chart moved by w = m z + s (m: the
/// chart's rotation times its scale): w -> a w + (m b + (1 - a) s).
std::complex<double> moved_translation(std::complex<double> a, std::complex<double> b,
                                       std::complex<double> m, std::complex<double> s) {
  return m * b + (1.0 - a) * s;
}

std::string describe(const ComponentParam& c, int index) {
  return "component " + std::to_string(index) + " (" + std::to_string(c.faces.size()) +
         " faces, genus " + std::to_string(c.genus) + ", " + std::to_string(c.boundary_loops) +
         " boundary loops)";
}

/// How far (radians) a vertex's angle in the layout may be from the flat metric's: the sum of
/// its corners' atan2 angles carries rounding of ~1e-12 per corner, while a vertex wrapped twice
/// is off by 2 pi; 1e-6 is far from both.
constexpr double kVertexAngleTolerance = 1e-6;

/// Interior vertices whose layout angle (over the corners of all their copies) is not the flat
/// metric's: 2 pi minus the cone's curvature, 2 pi elsewhere; with free seams 2 pi minus each
/// vertex's target curvature (to kVertexAngleTolerance).
int vertices_off_their_angle(const ParamResult& p, SeamMode seams) {
  const Mesh& mesh = p.mesh;
  const int nv = mesh.num_vertices();
  std::vector<double> angle(nv, 0), expected(nv, 2 * std::numbers::pi);
  std::vector<char> on_boundary(nv, 0);
  if (seams == SeamMode::Free && p.flow.target_curvature.size() == nv) {
    for (int v = 0; v < nv; ++v) expected[v] -= p.flow.target_curvature[v];
  } else {
    for (const Cone& c : p.cones) {
      if (c.vertex >= 0 && c.vertex < nv) expected[c.vertex] -= c.curvature;
    }
  }
  const Triangles& corners = p.cut_mesh.triangles;
  std::vector<std::array<int, 3>> edges;  // (smaller, larger, face) to find boundary edges
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d a = p.layout.uv.row(corners(f, k)).transpose();
      const Eigen::Vector2d b = p.layout.uv.row(corners(f, (k + 1) % 3)).transpose() - a;
      const Eigen::Vector2d c = p.layout.uv.row(corners(f, (k + 2) % 3)).transpose() - a;
      angle[mesh.triangles(f, k)] += std::atan2(b.x() * c.y() - b.y() * c.x(), b.dot(c));
      const int u = mesh.triangles(f, k), v = mesh.triangles(f, (k + 1) % 3);
      edges.push_back({std::min(u, v), std::max(u, v), f});
    }
  }
  numerics_detail::bucket_sort(edges, nv, [](const std::array<int, 3>& e) { return e[0]; });
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j][0] == edges[i][0] && edges[j][1] == edges[i][1]) ++j;
    if (j - i == 1) on_boundary[edges[i][0]] = on_boundary[edges[i][1]] = 1;
    i = j;
  }
  int off = 0;
  for (int v = 0; v < nv; ++v) {
    if (!on_boundary[v] && std::abs(angle[v] - expected[v]) > kVertexAngleTolerance &&
        angle[v] != 0)
      ++off;
  }
  return off;
}

/// The exact map's own checks (FoldFreeOptions): converged, closes up, finite, no face flipped or
/// degenerate. `why` says which failed.
bool passes_checks(const ParamResult& p, const ParamOptions& options, std::string& why) {
  if (!p.converged) {
    why = p.message.empty() ? "the flow did not converge" : p.message;
    return false;
  }
  if (!(p.layout.max_length_relative_error <= options.fold_free.max_length_error) ||
      !p.layout.uv.allFinite()) {
    std::ostringstream error;
    error << std::setprecision(3) << p.layout.max_length_relative_error;
    why = "the layout does not close up (relative length error " + error.str() +
          "): the flat metric's scale spans more than double precision lays out";
    return false;
  }
  const int folded = p.distortion.flipped_faces + p.distortion.degenerate_faces;
  if (folded > 0) {
    why = std::to_string(folded) + " faces stay flipped or degenerate after untangling (" +
          std::to_string(p.untangle.stuck_faces) +
          " with no vertex free to move, or around a cone whose angle its faces cannot hold)";
    return false;
  }
  // Every face positive, yet a vertex could still be wrapped twice (angle 4 pi where the metric
  // says 2 pi): the layout's angle at every interior vertex must be the metric's.
  const int off = vertices_off_their_angle(p, options.seams);
  if (off > 0) {
    why = std::to_string(off) + " vertices have another angle in the layout than the flat metric";
    return false;
  }
  return true;
}

/// Free seams' maps in doubt (kFreeSeamsCheckEnergy): E above twice the linearised choice's
/// promise, when above this floor (a flat map's E of 1e-20 may well be twice its promise).
constexpr double kFreeSeamsBreakdownRatio = 2;
constexpr double kFreeSeamsBreakdownFloor = 0.05;
/// The rigid map may distort angles this much more (relative, mean) and still replace the free
/// seams' map with its lower E: the rigid map of a torus or a free boundary can be as conformal.
constexpr double kRigidAngleSlack = 0.05;

bool free_map_in_doubt(const ParamResult& p, const ParamOptions& options) {
  if (options.seams != SeamMode::Free || !p.converged) return false;
  const double e = p.distortion.area_distortion_energy;
  return e > kFreeSeamsCheckEnergy ||
         (e > kFreeSeamsBreakdownFloor &&
          e > kFreeSeamsBreakdownRatio * p.seam_curvature.linear_area_energy);
}

/// The pipeline's exact map of one component; with free seams in doubt (free_map_in_doubt), also
/// the rigid map of the same cone option, kept when it passes its checks and distorts less
/// (kFreeSeamsCheckEnergy). A rigid map the options cannot make (too few cones for its
/// curvature) leaves the free one as it was. `unfolds_after`: a component of a larger mesh,
/// whose map gives way to its own shape when far from conformal (unfold_if_distorted): a free
/// map that will is left to it (the small gears of a CAD part: E 1e-29 unfolded, 0.024 rigid).
ParamResult exact_map(const Mesh& mesh, const ParamOptions& options, const Topology& topology,
                      bool unfolds_after) {
  ParamResult free = parameterize_one_component(mesh, options, topology);
  if (!free_map_in_doubt(free, options)) return free;
  // One that fails its checks is left to the routes that stand in for it: unfolded in its own
  // shape or as charts, CAD parts get maps of E 1e-28 where their rigid maps have 1 to 3.
  std::string why;
  if (!passes_checks(free, options, why)) return free;
  if (unfolds_after && free.distortion.angle_distortion_max > kUnfoldAbove &&
      develop_patches(mesh, options.polygons).num_patches == 1) {
    return free;
  }
  ParamOptions rigid_options = options;
  rigid_options.seams = SeamMode::Rigid;
  // Said when the free map stays, though it distorts strongly.
  const auto keep_free = [&](ParamResult& kept) {
    const double e = kept.distortion.area_distortion_energy;
    if (kept.converged && e > kFreeSeamsCheckEnergy) {
      std::ostringstream note;
      note << std::setprecision(3) << "the map with free seams distorts strongly (E " << e
           << ", where the linearised choice of their curvature promised "
           << kept.seam_curvature.linear_area_energy
           << "), and no rigid map with the same cone option does better";
      kept.free_seams_note = note.str();
    }
    return std::move(kept);
  };
  ParamResult rigid;
  try {
    rigid = parameterize_one_component(mesh, rigid_options, topology);
  } catch (const Error&) {
    return keep_free(free);
  }
  free.seam_curvature.free_area_energy = free.distortion.area_distortion_energy;
  free.seam_curvature.rigid_area_energy = rigid.distortion.area_distortion_energy;
  const Distortion& f = free.distortion;
  const Distortion& r = rigid.distortion;
  const bool keep_rigid =
      passes_checks(rigid, rigid_options, why) &&
      r.area_distortion_energy < f.area_distortion_energy &&
      r.angle_distortion_mean <= (1 + kRigidAngleSlack) * f.angle_distortion_mean;
  if (!keep_rigid) {
    free.seconds += rigid.seconds;
    return keep_free(free);
  }
  SeamCurvature& s = rigid.seam_curvature;
  s.rigid_kept = true;
  s.free_seconds = free.seam_curvature.free_seconds;
  s.linear_area_energy = free.seam_curvature.linear_area_energy;
  s.capped_vertices = free.seam_curvature.capped_vertices;
  s.free_area_energy = free.seam_curvature.free_area_energy;
  s.rigid_area_energy = free.seam_curvature.rigid_area_energy;
  // (Its word on too few cones for rigid seams does not hold: the free ones did worse.)
  rigid.too_few_cones.clear();
  std::ostringstream note;
  note << std::setprecision(3) << "the map with free seams distorted more (E "
       << f.area_distortion_energy << ", angle distortion " << f.angle_distortion_mean
       << ") than the one with rigid seams and the same cone option (E " << r.area_distortion_energy
       << ", angle distortion " << r.angle_distortion_mean
       << "), which is kept: rigid seams are free seams that carry no curvature";
  rigid.free_seams_note = note.str();
  rigid.seconds += free.seconds;
  return rigid;
}

/// FlowOptions::stall_iterations where the charts route may take over: a flow that has not
/// halved its error in 30 Newton iterations is not converging (the corpus's converging flows
/// halve it at nearly every iteration once past their first damped steps).
constexpr int kStallIterationsWithCharts = 30;

/// Whether an exception of the exact map gives way to the other routes: cones whose count was
/// left to ricci and still cannot carry the curvature. The user's own choices (their cones, a
/// count of automatic cones, no cones, one cone) are refused as they are, with the options that
/// work, since the user asked for exactly that map.
bool may_replace_refusal(const ParamOptions& options) {
  return options.fold_free.charts &&
         (options.cone_mode == ConeMode::Needed ||
          (options.cone_mode == ConeMode::Auto && options.auto_cones.count == 0));
}

/// User cones go to the component of their vertex, in its local numbering.
/// \throw InvalidInput for a cone on no vertex of a face
std::vector<std::vector<Cone>> user_cones_by_component(const Topology& topology, int num_vertices,
                                                       const ParamOptions& options) {
  std::vector<std::vector<Cone>> user_cones(topology.components.size());
  if (options.cone_mode != ConeMode::User) return user_cones;
  std::vector<int> local(num_vertices, -1);
  for (const Component& c : topology.components) {
    for (std::size_t i = 0; i < c.vertices.size(); ++i) local[c.vertices[i]] = static_cast<int>(i);
  }
  for (const Cone& cone : options.cones) {
    if (cone.vertex < 0 || cone.vertex >= num_vertices ||
        topology.vertex_component[cone.vertex] < 0) {
      throw InvalidInput("parameterize: cone vertex " + std::to_string(cone.vertex) +
                         " is not a vertex of any face");
    }
    user_cones[topology.vertex_component[cone.vertex]].push_back(
        {local[cone.vertex], cone.curvature});
  }
  return user_cones;
}

/// What the exact map on one component came to, besides its piece.
struct ExactMapOutcome {
  /// The user's own choice (their cones, a count) refused: the component is laid out still, but
  /// reported as failed, since what was asked was not made.
  bool refused_choice = false;
  bool cancelled = false;  ///< the progress callback stopped one of its flows
};

/// The pipeline's exact map on one component (or the one `done` already, or the refusal already
/// met), judged by its own checks: sets info.param, parameterized, method and message, and the
/// piece's exact_flipped.
ExactMapOutcome run_exact_map(Piece& piece, const Mesh& sub, const Polygons& polygons,
                              const std::vector<Cone>& cones, const ParamOptions& options,
                              bool only_component, ParamResult* done, const std::string& refusal) {
  ComponentParam& info = piece.info;
  ExactMapOutcome outcome;
  ParamOptions component_options = options;
  component_options.cones = cones;
  component_options.polygons = polygons;
  // Whichever flow the progress callback stops (cone settling included), stop here too.
  if (options.flow.progress) {
    component_options.flow.progress = [&](const IterationRecord& record) {
      const bool go = options.flow.progress(record);
      outcome.cancelled = outcome.cancelled || !go;
      return go;
    };
  }
  if (done != nullptr) {
    info.param = std::move(*done);  // a single component's exact map, done already
  } else if (!refusal.empty()) {
    info.message = refusal;  // ... which was refused
  } else {
    try {
      info.param =
          exact_map(sub, component_options, build_topology(sub.triangles, sub.num_vertices()),
                    /*unfolds_after=*/true);
    } catch (const InvalidInput& e) {
      if (only_component && !may_replace_refusal(options)) throw;
      outcome.refused_choice = !may_replace_refusal(options);
      info.param = ParamResult{};
      info.message = e.what();
    } catch (const Error& e) {
      info.param = ParamResult{};
      info.message = e.what();
    }
  }
  std::string why;
  info.parameterized = info.message.empty() && passes_checks(info.param, options, why);
  if (info.message.empty()) info.message = why;
  if (info.parameterized) {
    info.method =
        info.param.untangle.moved_vertices > 0 ? ComponentMethod::Untangled : ComponentMethod::Flow;
    info.message.clear();
  }
  piece.exact_flipped = info.param.untangle.flipped_before;
  return outcome;
}

/// A valid flow layout that is far from conformal somewhere (the few cones a tiny closed part
/// needs, on a needle-shaped tetrahedron) gives way to the component's own shape when that lays
/// out in one piece: it has no distortion at all.
void unfold_if_distorted(ComponentParam& info, const Mesh& sub, const Polygons& polygons) {
  if (!info.parameterized || !(info.param.distortion.angle_distortion_max > kUnfoldAbove)) return;
  PatchLayout patches = develop_patches(sub, polygons);
  if (patches.num_patches != 1) return;
  info.message = "the flow's layout distorts angles by up to " +
                 std::to_string(info.param.distortion.angle_distortion_max) +
                 " (sigma_max / sigma_min)";
  info.method = ComponentMethod::Unfolded;
  info.param = unfolded_result(sub, patches, polygons);
}

/// The charts route on a component whose exact map failed: cut through the failed map's cones
/// (its cut relieved the curvature there).
void lay_out_as_charts(Piece& piece, const Mesh& sub, const Polygons& polygons,
                       const ParamOptions& options, bool refused_choice) {
  ComponentParam& info = piece.info;
  const auto charts_start = Clock::now();
  std::vector<int> cut_through;
  for (const Cone& cone : info.param.cones) {
    if (cone.vertex < sub.num_vertices()) cut_through.push_back(cone.vertex);
  }
  ParamOptions chart_options = options;
  chart_options.flow.progress = {};
  chart_options.polygons = polygons;
  ChartsLayout charts = lay_out_charts(sub, chart_options, cut_through);
  // The failed map's word on its cone count stays: it says why the charts stood in.
  std::string too_few_cones = std::move(info.param.too_few_cones);
  const ConeRefinementReport cone_refinement = info.param.cone_refinement;
  info.param = charts_result(sub, charts, polygons);
  info.param.too_few_cones = std::move(too_few_cones);
  info.param.cone_refinement = cone_refinement;
  info.param.timings.charts = seconds_since(charts_start);
  info.method = ComponentMethod::Charts;
  info.parameterized = !refused_choice;
  info.message += "; laid out as " + charts.message;
  piece.face_chart = std::move(charts.face_chart);
  piece.num_charts = charts.num_charts;
}

/// The last resort: the component's own shape in `patches` (several, none overlapping), each its
/// own chart; the failed pipeline's result stays in info.param for its diagnostics.
void lay_out_as_patches(Piece& piece, const Mesh& sub, const Polygons& polygons,
                        PatchLayout& patches) {
  ComponentParam& info = piece.info;
  info.method = ComponentMethod::Patches;
  if (!info.message.empty()) info.message += "; ";
  info.message +=
      "its own shape needs " + std::to_string(patches.num_patches) + " patches not to overlap";
  // The failed pipeline's result stays for its diagnostics, on the component itself.
  info.param.mesh = sub;
  info.param.vertex_origin.resize(sub.num_vertices());
  std::iota(info.param.vertex_origin.begin(), info.param.vertex_origin.end(), 0);
  info.param.added_vertex_parents.clear();
  info.param.edge_splits = 0;
  info.param.subdivided = false;
  info.distortion = measure_polygon_distortion(
      sub, start_fans_where_valid(polygons, sub, patches.triangles, patches.layout),
      patches.triangles, patches.layout);
  piece.cut_triangles = std::move(patches.triangles);
  piece.cut_vertex = std::move(patches.vertex);
  piece.layout = std::move(patches.layout);
  piece.face_chart = std::move(patches.face_patch);
  piece.num_charts = patches.num_patches;
  piece.cut_edges.resize(patches.is_glued_edge.size());
  const Topology t = build_topology(sub.triangles, sub.num_vertices());
  for (int e = 0; e < t.num_edges; ++e) {
    piece.cut_edges[e] = !t.is_boundary_edge[e] && !patches.is_glued_edge[e];
  }
}

/// A component the exact map did not parameterize: unfolded in one piece, else laid out as
/// charts (when allowed), else as patches of its own shape.
void lay_out_failed(Piece& piece, const Mesh& sub, const Polygons& polygons,
                    const ParamOptions& options, bool refused_choice) {
  ComponentParam& info = piece.info;
  PatchLayout patches = develop_patches(sub, polygons);
  if (patches.num_patches == 1) {
    info.method = ComponentMethod::Unfolded;
    info.parameterized = true;
    info.param = unfolded_result(sub, patches, polygons);
  } else if (options.fold_free.charts) {
    lay_out_as_charts(piece, sub, polygons, options, refused_choice);
  } else {
    lay_out_as_patches(piece, sub, polygons, patches);
  }
}

/// A layout that overlaps itself (a flat metric cut open into one disk can wind over itself) cut
/// into pieces that do not, each its own chart, the pieces' shared vertices copied (one per fan
/// of each piece).
void split_overlapping_layout(Piece& piece) {
  int count = 0;
  piece.face_chart = embedded_pieces(piece.layout, piece.cut_triangles, count,
                                     piece.info.param.polygons.triangle_polygon);
  piece.num_charts = count;
  const std::vector<int> source =
      split_at_charts(piece.cut_triangles, static_cast<int>(piece.layout.rows()), piece.face_chart);
  std::vector<int> vertex(source.size());
  Points positions(static_cast<Eigen::Index>(source.size()), 2);
  for (std::size_t v = 0; v < source.size(); ++v) {
    vertex[v] = piece.cut_vertex[source[v]];
    positions.row(static_cast<Eigen::Index>(v)) = piece.layout.row(source[v]);
  }
  piece.cut_vertex = std::move(vertex);
  piece.layout = std::move(positions);
}

/// The piece's cut mesh and layout from its route's result (every route but Patches, which
/// lays its piece out itself): the layout scaled to the component's 3D area, split where it
/// overlaps itself.
void take_route_layout(Piece& piece) {
  ComponentParam& info = piece.info;
  const ParamResult& p = info.param;
  piece.cut_triangles = p.cut_mesh.triangles;
  piece.cut_vertex = p.cut_mesh.to_original;
  info.area_scale = p.distortion.layout_area > 0
                        ? std::sqrt(p.distortion.surface_area / p.distortion.layout_area)
                        : 1.0;
  piece.layout = p.layout.uv * info.area_scale;
  info.distortion = p.distortion;
  info.seam_length = p.seam_length;
  // (Charts are laid out as pieces that do not overlap, on top of each other.)
  info.overlapping_face_pairs =
      info.method == ComponentMethod::Charts
          ? 0
          : find_uv_overlaps(p.layout.uv, p.cut_mesh.triangles, {}, 0).count;
  if (info.overlapping_face_pairs > 0) split_overlapping_layout(piece);
}

/// One component on its own: the pipeline, else its own shape, as one patch or several, else
/// charts. Returns false when the progress callback cancelled its flow (the piece then holds
/// the exact map's outcome only).
bool route_component(Piece& piece, const Component& component, const Submesh& submesh,
                     const std::vector<Cone>& cones, const ParamOptions& options,
                     bool only_component, ParamResult* done, const std::string& refusal) {
  const auto component_start = Clock::now();
  const Mesh& sub = submesh.mesh;
  ComponentParam& info = piece.info;
  info.vertices = component.vertices;
  info.faces = component.faces;
  info.euler_characteristic = component.euler_characteristic;
  info.genus = component.genus;
  info.boundary_loops = component.num_boundary_loops;
  bool refused_choice = false;
  const Polygons polygons = polygons_of_faces(options.polygons, submesh.face_map);
  if (sub.num_faces() > 2) {
    const ExactMapOutcome exact =
        run_exact_map(piece, sub, polygons, cones, options, only_component, done, refusal);
    if (exact.cancelled) return false;
    refused_choice = exact.refused_choice;
  }
  unfold_if_distorted(info, sub, polygons);
  if (!info.parameterized) lay_out_failed(piece, sub, polygons, options, refused_choice);
  if (info.method != ComponentMethod::Patches) take_route_layout(piece);
  info.seconds = seconds_since(component_start);
  return true;
}

/// Each component's vertices in the whole mesh: its own where it has them, then the ones its
/// edge splits added, after the input's, component after component.
int map_component_vertices(std::vector<Piece>& pieces, int num_input_vertices) {
  int num_vertices = num_input_vertices;
  for (Piece& piece : pieces) {
    ComponentParam& info = piece.info;
    const Mesh& m = info.param.mesh;
    info.vertex_map.resize(m.num_vertices());
    for (int i = 0; i < m.num_vertices(); ++i) {
      info.vertex_map[i] =
          i < static_cast<int>(info.vertices.size()) ? info.vertices[i] : num_vertices++;
    }
  }
  return num_vertices;
}

/// The whole mesh: the input's vertices, then each component's added ones; the input's faces in
/// order, a component whose faces changed giving all of its faces at its first. Sets the pieces'
/// vertex_map and face_map, and the result's mesh, vertex_origin, added_vertex_parents,
/// edge_splits and subdivided.
void gather_mesh(std::vector<Piece>& pieces, const Mesh& input, const Topology& topology,
                 MeshParamResult& result) {
  const int nv_in = input.num_vertices();
  const int num_vertices = map_component_vertices(pieces, nv_in);
  result.mesh.positions.resize(num_vertices, 3);
  result.mesh.positions.topRows(nv_in) = input.positions;
  result.vertex_origin.assign(num_vertices, -1);
  std::iota(result.vertex_origin.begin(), result.vertex_origin.begin() + nv_in, 0);
  for (const Piece& piece : pieces) {
    const ComponentParam& info = piece.info;
    const ParamResult& p = info.param;
    for (int i = static_cast<int>(info.vertices.size()); i < p.mesh.num_vertices(); ++i) {
      result.mesh.positions.row(info.vertex_map[i]) = p.mesh.positions.row(i);
    }
    for (const auto& [a, b] : p.added_vertex_parents) {
      result.added_vertex_parents.push_back({info.vertex_map[a], info.vertex_map[b]});
    }
    result.edge_splits += p.edge_splits;
    result.subdivided = result.subdivided || p.subdivided;
  }
  std::vector<int> local_face(input.num_faces());
  for (const Component& c : topology.components) {
    for (std::size_t i = 0; i < c.faces.size(); ++i) local_face[c.faces[i]] = static_cast<int>(i);
  }
  std::vector<std::array<int, 3>> faces;
  faces.reserve(input.num_faces());
  auto emit = [&](Piece& piece, int j) {
    piece.info.face_map[j] = static_cast<int>(faces.size());
    const Triangles& t = piece.info.param.mesh.triangles;
    faces.push_back({piece.info.vertex_map[t(j, 0)], piece.info.vertex_map[t(j, 1)],
                     piece.info.vertex_map[t(j, 2)]});
  };
  for (Piece& piece : pieces) piece.info.face_map.resize(piece.info.param.mesh.num_faces());
  for (int f = 0; f < input.num_faces(); ++f) {
    Piece& piece = pieces[topology.face_component[f]];
    const bool unchanged =
        piece.info.param.mesh.num_faces() == static_cast<int>(piece.info.faces.size());
    if (unchanged) {
      emit(piece, local_face[f]);
    } else if (local_face[f] == 0) {
      for (int j = 0; j < piece.info.param.mesh.num_faces(); ++j) emit(piece, j);
    }
  }
  result.mesh.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k)
      result.mesh.triangles(static_cast<Eigen::Index>(f), k) = faces[f][k];
  }
}

/// The atlas before packing, in whole-mesh faces.
struct UnpackedAtlas {
  Points layout;                ///< per cut-mesh vertex, component after component
  Triangles cut_triangles;      ///< #F of the whole mesh by 3
  std::vector<int> face_chart;  ///< #F of the whole mesh: its chart
};

/// The cut mesh and the layout before packing, component after component, and the charts: one
/// per component, one per piece of a layout split or patch of a Patches component. Sets the
/// pieces' cut_vertex_offset and charts, and the result's cut_mesh.to_original.
UnpackedAtlas gather_unpacked_atlas(std::vector<Piece>& pieces, MeshParamResult& result) {
  int num_cut_vertices = 0, num_charts = 0;
  for (Piece& piece : pieces) {
    piece.info.cut_vertex_offset = num_cut_vertices;
    num_cut_vertices += static_cast<int>(piece.layout.rows());
    for (int k = 0; k < piece.num_charts; ++k) piece.info.charts.push_back(num_charts++);
  }
  UnpackedAtlas atlas{Points(num_cut_vertices, 2), Triangles(result.mesh.num_faces(), 3),
                      std::vector<int>(result.mesh.num_faces())};
  result.cut_mesh.to_original.resize(num_cut_vertices);
  for (Piece& piece : pieces) {
    ComponentParam& info = piece.info;
    const int offset = info.cut_vertex_offset;
    atlas.layout.middleRows(offset, piece.layout.rows()) = piece.layout;
    for (std::size_t i = 0; i < piece.cut_vertex.size(); ++i) {
      result.cut_mesh.to_original[offset + i] = info.vertex_map[piece.cut_vertex[i]];
    }
    for (int j = 0; j < piece.cut_triangles.rows(); ++j) {
      atlas.cut_triangles.row(info.face_map[j]) = piece.cut_triangles.row(j).array() + offset;
      atlas.face_chart[info.face_map[j]] =
          info.charts[piece.face_chart.empty() ? 0 : piece.face_chart[j]];
    }
  }
  return atlas;
}

/// The charts packed into the unit square: the result's packing, uv (and layout.uv, its layout
/// units), cut mesh, polygons and distortion.
void pack_atlas(UnpackedAtlas atlas, const ParamOptions& options, MeshParamResult& result) {
  const int num_cut_vertices = static_cast<int>(atlas.layout.rows());
  result.packing =
      pack_charts(atlas.layout, atlas.cut_triangles, atlas.face_chart, options.packing);
  result.uv = std::move(result.packing.uv);
  result.packing.uv.resize(0, 2);
  result.uv_scale = result.packing.scale;
  result.uv_offset = Eigen::Vector2d::Zero();
  result.layout.uv = result.uv / result.packing.scale;
  result.cut_mesh.triangles = std::move(atlas.cut_triangles);
  result.cut_mesh.topology = build_topology(result.cut_mesh.triangles, num_cut_vertices);
  // The input's polygons are the whole mesh's when no component changed its faces.
  if (result.edge_splits == 0 && !result.subdivided) {
    result.polygons =
        start_fans_where_valid(options.polygons, result.mesh, result.cut_mesh.triangles, result.uv);
  }
  result.distortion = measure_polygon_distortion(result.mesh, result.polygons,
                                                 result.cut_mesh.triangles, result.uv);
}

/// Per edge of a component's own mesh: the edge of the whole mesh.
std::vector<int> whole_mesh_edges(const ComponentParam& info, const Topology& local,
                                  const Topology& whole) {
  std::vector<int> edge_map(local.num_edges, -1);
  for (int j = 0; j < local.num_faces; ++j) {
    for (int k = 0; k < 3; ++k) {
      edge_map[local.halfedge_edge[3 * j + k]] = whole.halfedge_edge[3 * info.face_map[j] + k];
    }
  }
  return edge_map;
}

/// A Patches component's seams (the edges between its patches) in the whole mesh's cut.
void gather_patch_seams(const Piece& piece, ComponentParam& info, const Topology& local,
                        const std::vector<int>& edge_map, MeshParamResult& result) {
  const Eigen::VectorXd lengths = input_edge_lengths(info.param.mesh, local);
  for (int e = 0; e < local.num_edges; ++e) {
    if (!piece.cut_edges[e]) continue;
    result.cut.is_cut_edge[edge_map[e]] = 1;
    info.seam_length += lengths[e];
  }
  result.cut.length += info.seam_length;
  result.seam_length += info.seam_length;
}

/// A component's cones and cut in the whole mesh's: its cut edges, the edges between the
/// pieces of a layout split so as not to overlap itself (seams too), nodes and segments.
void gather_cones_and_cut(const Piece& piece, ComponentParam& info, const Topology& local,
                          const std::vector<int>& edge_map, MeshParamResult& result) {
  const ParamResult& p = info.param;
  for (const Cone& cone : p.cones)
    info.cones.push_back({info.vertex_map[cone.vertex], cone.curvature});
  result.cones.insert(result.cones.end(), info.cones.begin(), info.cones.end());
  for (int e = 0; e < local.num_edges; ++e) {
    if (p.cut.is_cut_edge[e]) result.cut.is_cut_edge[edge_map[e]] = 1;
  }
  if (info.charts.size() > 1) {
    // Split so as not to overlap itself: the edges between its pieces are seams too.
    const Eigen::VectorXd lengths = input_edge_lengths(p.mesh, local);
    const std::vector<int>& chart = piece.face_chart;
    for (int e = 0; e < local.num_edges; ++e) {
      const int h0 = local.edge_halfedges(e, 0), h1 = local.edge_halfedges(e, 1);
      if (h0 < 0 || h1 < 0 || p.cut.is_cut_edge[e]) continue;
      if (chart[Topology::face_of(h0)] == chart[Topology::face_of(h1)]) continue;
      result.cut.is_cut_edge[edge_map[e]] = 1;
      info.seam_length += lengths[e];
    }
  }
  for (int v : p.cut.nodes) result.cut.nodes.push_back(info.vertex_map[v]);
  for (const std::vector<int>& segment : p.cut.segments) {
    std::vector<int>& moved = result.cut.segments.emplace_back();
    for (int v : segment) moved.push_back(info.vertex_map[v]);
  }
  result.cut.num_generators += p.cut.num_generators;
  result.cut.length += p.cut.length;
  result.seam_length += info.seam_length;
}

/// A component's transitions and boundary charts moved with its chart from its own layout to
/// the atlas's layout units (w = m z + s), its segments numbered after `segment_offset`; a
/// layout split into pieces moves piece by piece, so its transitions and atlas stay in
/// components[c].param. Also the layout's and atlas's figures over the components.
void move_chart_stages(const ComponentParam& info, const std::vector<int>& edge_map,
                       int segment_offset, MeshParamResult& result) {
  const ParamResult& p = info.param;
  const bool one_chart = info.charts.size() == 1;
  const PackedChart& chart = result.packing.charts[info.charts.front()];
  const std::complex<double> m = std::polar(info.area_scale, chart.rotation);
  const std::complex<double> s =
      std::complex<double>(chart.translation.x(), chart.translation.y()) / result.packing.scale;
  auto move_transition = [&](SeamTransition t) {
    t.edge = t.edge >= 0 ? edge_map[t.edge] : -1;
    if (t.segment >= 0) t.segment += segment_offset;
    t.translation = moved_translation(t.rotation, t.translation, m, s);
    return t;
  };
  for (const SeamTransition& t : one_chart ? p.layout.transitions : std::vector<SeamTransition>{}) {
    result.layout.transitions.push_back(move_transition(t));
  }
  for (const SeamTransition& t :
       one_chart ? p.layout.segment_transitions : std::vector<SeamTransition>{}) {
    result.layout.segment_transitions.push_back(move_transition(t));
  }
  result.layout.max_length_relative_error =
      std::max(result.layout.max_length_relative_error, p.layout.max_length_relative_error);
  result.layout.num_flipped_faces += p.layout.num_flipped_faces;
  result.layout.refined = result.layout.refined || p.layout.refined;
  for (BoundaryChart bc : one_chart ? p.atlas.boundary_charts : std::vector<BoundaryChart>{}) {
    bc.segment += segment_offset;
    for (int& f : bc.faces) f = info.face_map[f];
    for (Eigen::Index i = 0; i < bc.corner_uv.rows(); ++i) {
      for (int k = 0; k < 3; ++k) {
        const std::complex<double> w =
            m * std::complex<double>(bc.corner_uv(i, 2 * k), bc.corner_uv(i, 2 * k + 1)) + s;
        bc.corner_uv(i, 2 * k) = w.real();
        bc.corner_uv(i, 2 * k + 1) = w.imag();
      }
    }
    bc.translation = moved_translation(bc.rotation, bc.translation, m, s);
    result.atlas.boundary_charts.push_back(std::move(bc));
  }
  result.atlas.max_transition_error =
      std::max(result.atlas.max_transition_error, p.atlas.max_transition_error);
}

/// Adds a component's untangling to the whole mesh's.
void add_untangle(const UntangleResult& from, UntangleResult& to) {
  to.flipped_before += from.flipped_before;
  to.flipped_after += from.flipped_after;
  to.stuck_faces += from.stuck_faces;
  to.moved_vertices += from.moved_vertices;
  to.region_faces += from.region_faces;
  to.rounds += from.rounds;
  to.newton_iterations += from.newton_iterations;
  to.seconds += from.seconds;
}

/// Adds a Flow or Untangled component's stage timings, polish (its face means weighted by the
/// component's face count, divided by `polish_faces` at the end) and flow (in whole-mesh
/// vertices) to the whole mesh's.
void add_exact_map_stages(const ComponentParam& info, double& polish_faces,
                          MeshParamResult& result) {
  const ParamResult& p = info.param;
  const ParamTimings& t = p.timings;
  result.timings.cones += t.cones, result.timings.flow += t.flow, result.timings.cut += t.cut;
  result.timings.development += t.development, result.timings.layout += t.layout;
  result.timings.atlas += t.atlas, result.timings.distortion += t.distortion;
  result.timings.polish += t.polish, result.timings.untangle += t.untangle;
  const double faces_here = static_cast<double>(p.mesh.num_faces());
  result.polish.free_vertices += p.polish.free_vertices;
  result.polish.moved_vertices += p.polish.moved_vertices;
  result.polish.untangled_faces += p.polish.untangled_faces;
  result.polish.sweeps = std::max(result.polish.sweeps, p.polish.sweeps);
  result.polish.seconds += p.polish.seconds;
  if (std::isfinite(p.polish.angle_distortion_before)) {
    result.polish.angle_distortion_before += faces_here * p.polish.angle_distortion_before;
    result.polish.angle_distortion_after += faces_here * p.polish.angle_distortion_after;
    polish_faces += faces_here;
  }
  const MeshFlowResult& flow = p.flow;
  result.flow.converged = result.flow.converged && flow.converged;
  result.flow.max_error = std::max(result.flow.max_error, flow.max_error);
  result.flow.intrinsic.add_flip_counts(flow.intrinsic);
  result.flow.setup_seconds += flow.setup_seconds;
  result.flow.total_seconds += flow.total_seconds;
  for (ComponentFlow cf : flow.components) {
    for (int& v : cf.vertices) v = info.vertex_map[v];
    result.flow.components.push_back(std::move(cf));
  }
  for (int i = 0; i < p.mesh.num_vertices(); ++i) {
    result.flow.u[info.vertex_map[i]] = flow.u[i];
    result.flow.curvature[info.vertex_map[i]] = flow.curvature[i];
    result.flow.target_curvature[info.vertex_map[i]] = flow.target_curvature[i];
  }
}

/// The stages in whole-mesh indices, component after component: cut, cones, transitions,
/// atlas, untangling, and for the exact map's components timings, polish and flow.
void gather_stages(std::vector<Piece>& pieces, MeshParamResult& result) {
  const int num_vertices = result.mesh.num_vertices();
  const Topology whole = build_topology(result.mesh.triangles, num_vertices);
  result.cut.is_cut_edge.assign(whole.num_edges, 0);
  result.flow.converged = true;
  result.flow.u = Eigen::VectorXd::Zero(num_vertices);
  result.flow.curvature = Eigen::VectorXd::Zero(num_vertices);
  result.flow.target_curvature = Eigen::VectorXd::Zero(num_vertices);
  result.flow.target.description = "flat, per component";
  int segment_offset = 0;
  double polish_faces = 0;
  for (Piece& piece : pieces) {
    ComponentParam& info = piece.info;
    const ParamResult& p = info.param;
    const Topology local = build_topology(p.mesh.triangles, p.mesh.num_vertices());
    const std::vector<int> edge_map = whole_mesh_edges(info, local, whole);
    if (info.method == ComponentMethod::Patches) {
      gather_patch_seams(piece, info, local, edge_map, result);
      continue;
    }
    gather_cones_and_cut(piece, info, local, edge_map, result);
    move_chart_stages(info, edge_map, segment_offset, result);
    segment_offset += static_cast<int>(p.cut.segments.size());
    result.timings.charts += p.timings.charts;
    add_untangle(p.untangle, result.untangle);
    if (info.method != ComponentMethod::Flow && info.method != ComponentMethod::Untangled) continue;
    add_exact_map_stages(info, polish_faces, result);
  }
  std::sort(result.layout.transitions.begin(), result.layout.transitions.end(),
            [](const SeamTransition& a, const SeamTransition& b) { return a.edge < b.edge; });
  if (polish_faces > 0) {
    result.polish.angle_distortion_before /= polish_faces;
    result.polish.angle_distortion_after /= polish_faces;
  }
}

/// The verdict: converged when every component was parameterized; else the message names the
/// failed ones (the first five).
void judge_components(const std::vector<Piece>& pieces, MeshParamResult& result) {
  const int num_components = static_cast<int>(pieces.size());
  int failed = 0;
  for (int c = 0; c < num_components; ++c) {
    const ComponentParam& info = pieces[c].info;
    if (info.parameterized) continue;
    if (failed < 5) {
      result.message += (failed ? "; " : "") + describe(info, c) + ": " + info.message;
    }
    ++failed;
  }
  result.converged = failed == 0;
  if (failed > 0) {
    result.message =
        std::to_string(failed) + " of " + std::to_string(num_components) +
        " components failed (laid out as charts or patches of their own shape): " + result.message +
        (failed > 5 ? "; ..." : "");
  }
}

/// The route of a component that went through the atlas's path.
ComponentRoute route_of(const Piece& piece) {
  const ComponentParam& info = piece.info;
  ComponentRoute route;
  route.method = info.method;
  route.charts = static_cast<int>(info.charts.size());
  route.seam_length = info.seam_length;
  route.flipped_before = piece.exact_flipped;
  route.flipped = info.distortion.flipped_faces;
  if (info.method != ComponentMethod::Flow && info.method != ComponentMethod::Untangled) {
    route.why = info.message;
  }
  route.pipeline = info.param;
  return route;
}

/// The atlas's path: each component routed on its own (route_component), then gathered into
/// the whole mesh (gather_mesh), its charts packed (gather_unpacked_atlas, pack_atlas), its
/// stages moved into whole-mesh indices (gather_stages) and judged (judge_components).
/// `first_attempt` / `first_why`: a single component's exact map, done already or refused.
MeshParamResult parameterize_components(const Mesh& input, const Topology& topology,
                                        const ParamOptions& options, ParamResult* first_attempt,
                                        const std::string& first_why) {
  const auto start = Clock::now();
  const int num_components = static_cast<int>(topology.components.size());
  const std::vector<std::vector<Cone>> user_cones =
      user_cones_by_component(topology, input.num_vertices(), options);
  const std::vector<Submesh> submeshes = split_components(input, topology);
  std::vector<Piece> pieces(num_components);
  for (int c = 0; c < num_components; ++c) {
    Piece& piece = pieces[c];
    const bool done = route_component(
        piece, topology.components[c], submeshes[c], user_cones[c], options, num_components == 1,
        c == 0 ? first_attempt : nullptr, c == 0 ? first_why : std::string());
    if (!done) {
      // The progress callback asked to stop: no other component is started, no atlas made.
      MeshParamResult stopped;
      stopped.mesh = input;
      stopped.message =
          "parameterize: cancelled in component " + std::to_string(c) + ": " + piece.info.message;
      for (int d = 0; d <= c; ++d) stopped.components.push_back(std::move(pieces[d].info));
      stopped.seconds = seconds_since(start);
      return stopped;
    }
  }
  MeshParamResult result;
  gather_mesh(pieces, input, topology, result);
  pack_atlas(gather_unpacked_atlas(pieces, result), options, result);
  gather_stages(pieces, result);
  judge_components(pieces, result);
  for (const Piece& piece : pieces) result.routes.push_back(route_of(piece));
  result.components.reserve(num_components);
  for (Piece& piece : pieces) result.components.push_back(std::move(piece.info));
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace

const char* component_method_name(ComponentMethod method) {
  return enum_name(method);
}

MeshParamResult parameterize(const Mesh& mesh, const ParamOptions& user_options) {
  // With the charts to fall back on, a Newton flow that stalls gives way to them instead of
  // running out its iterations (minutes on a 24k-face genus-73 surface with one hole).
  ParamOptions options = user_options;
  if (options.fold_free.charts && options.flow.stall_iterations == 0) {
    options.flow.stall_iterations = kStallIterationsWithCharts;
  }
  check_polygons(options.polygons, mesh.triangles, "parameterize");
  Topology topology = build_topology(mesh.triangles, mesh.num_vertices());
  if (topology.components.size() > 1) {
    return parameterize_components(mesh, topology, options, nullptr, {});
  }
  // One component: the exact map, kept when it passes its checks (or when nothing else may
  // replace it); otherwise the components' path tries the other routes on it.
  ParamResult first;
  std::string why;
  bool refused = false;
  try {
    first = exact_map(mesh, options, topology, /*unfolds_after=*/false);
  } catch (const InvalidInput& e) {
    if (!may_replace_refusal(options)) throw;
    why = e.what();
    refused = true;
  }
  // A flow the progress callback cancelled ends the run as it is: the caller asked to stop, so
  // no other route starts (the result says Cancelled, converged false).
  const bool cancelled = !refused && first.flow.status == FlowStatus::Cancelled;
  if (cancelled) why = first.message;
  if (!refused && (cancelled || passes_checks(first, options, why) || !options.fold_free.charts)) {
    ComponentRoute route;
    route.method =
        first.untangle.moved_vertices > 0 ? ComponentMethod::Untangled : ComponentMethod::Flow;
    route.seam_length = first.seam_length;
    route.flipped_before = first.untangle.flipped_before;
    route.flipped = first.distortion.flipped_faces;
    if (!why.empty() && first.converged) route.why = why;
    route.pipeline = first;
    MeshParamResult whole;
    static_cast<Parameterization&>(whole) = std::move(first);
    whole.routes = {route};
    return whole;
  }
  const double first_seconds = first.seconds;
  // The exact map that failed its checks goes along (the charts cut through its cones); a
  // refusal goes as its message.
  MeshParamResult result = parameterize_components(mesh, topology, options,
                                                   refused ? nullptr : &first, refused ? why : "");
  result.seconds += first_seconds;
  return result;
}

}  // namespace ricci
