#include "json_output.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

namespace ricci::cli {
namespace {

nlohmann::json to_json(const IterationRecord& r) {
  return {{"iteration", r.iteration},   {"max_error", r.max_error},
          {"rms_error", r.rms_error},   {"step_length", r.step_length},
          {"backtracks", r.backtracks}, {"triangle_failures", r.triangle_failures},
          {"flips", r.flips},           {"seconds", r.seconds}};
}

nlohmann::json to_json(const FlowTimings& t) {
  return {{"setup", t.setup},       {"assembly", t.assembly},
          {"analysis", t.analysis}, {"factorization", t.factorization},
          {"solve", t.solve},       {"line_search", t.line_search},
          {"total", t.total}};
}

std::vector<double> to_vector(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

}  // namespace

nlohmann::json to_json(const MeshInfo& info) {
  nlohmann::json j = {{"vertices", info.vertices},
                      {"unreferenced_vertices", info.unreferenced_vertices},
                      {"edges", info.edges},
                      {"faces", info.faces},
                      {"components", info.components},
                      {"boundary_loops", info.boundary_loops},
                      {"euler_characteristic", info.euler_characteristic},
                      {"genus", info.genus},
                      {"min_angle_degrees", info.min_angle_degrees},
                      {"max_angle_degrees", info.max_angle_degrees},
                      {"bounding_box_diagonal", info.bounding_box_diagonal},
                      {"valid", info.validation.ok()}};
  nlohmann::json comps = nlohmann::json::array();
  for (const ComponentInfo& c : info.component_info) {
    comps.push_back({{"vertices", c.vertices},
                     {"edges", c.edges},
                     {"faces", c.faces},
                     {"boundary_loops", c.boundary_loops},
                     {"euler_characteristic", c.euler_characteristic},
                     {"genus", c.genus}});
  }
  j["component_info"] = comps;
  nlohmann::json counts = nlohmann::json::object();
  for (const auto& [kind, count] : info.validation.counts) counts[defect_name(kind)] = count;
  j["defect_counts"] = counts;
  nlohmann::json defects = nlohmann::json::array();
  for (const Defect& d : info.validation.defects) {
    defects.push_back(
        {{"kind", defect_name(d.kind)}, {"element", d.element}, {"message", d.message}});
  }
  j["defects"] = defects;
  return j;
}

nlohmann::json to_json(const RepairReport& report) {
  auto count = [](const RepairCount& c) {
    return nlohmann::json{{"count", c.count}, {"examples", c.examples}};
  };
  return {{"changed", report.changed()},
          {"input_vertices", report.input_vertices},
          {"input_faces", report.input_faces},
          {"output_vertices", report.output_vertices},
          {"output_faces", report.output_faces},
          {"welded_vertices", count(report.welded_vertices)},
          {"repeated_vertex_faces_removed", count(report.repeated_vertex_faces_removed)},
          {"duplicate_faces_removed", count(report.duplicate_faces_removed)},
          {"slivers_removed", count(report.slivers_removed)},
          {"boundary_slivers_removed", report.boundary_slivers_removed},
          {"faces_split", count(report.faces_split)},
          {"non_manifold_edges_split",
           {{"count", report.non_manifold_edges_split},
            {"examples", report.non_manifold_edge_examples}}},
          {"non_manifold_vertices_split", count(report.non_manifold_vertices_split)},
          {"vertex_copies_added", report.vertex_copies_added},
          {"faces_flipped", count(report.faces_flipped)},
          {"unreferenced_vertices_dropped", count(report.unreferenced_vertices_dropped)},
          {"smaller_components_removed", count(report.smaller_components_removed)},
          {"smaller_component_faces_removed", report.smaller_component_faces_removed},
          {"non_orientable_components", count(report.non_orientable_components)},
          {"zero_area_faces_left", count(report.zero_area_faces_left)},
          {"messages", report.messages}};
}

nlohmann::json flow_summary(const MeshFlowResult& result, const MeshFlowOptions& options) {
  nlohmann::json j;
  j["converged"] = result.converged;
  j["max_error"] = result.max_error;
  j["tolerance"] = options.flow.tolerance;
  j["scheme"] = scheme_name(options.structure.scheme);
  j["geometry"] = geometry_name(options.structure.geometry);
  if (options.structure.geometry == Geometry::Hyperbolic) {
    j["hyperbolic_length_scale"] = result.structure.structure.length_scale;
  }
  j["solver"] = flow_solver_name(options.flow.solver);
  j["flips"] = edge_flips_name(options.flow.flips);
  j["flipped_edges"] = result.intrinsic.flips();
  j["blocked_flips"] = result.intrinsic.blocked_flips();
  j["target"] = result.target.description;
  j["fit_rms_relative_error"] = result.structure.fit_rms_relative_error;
  j["fit_max_relative_error"] = result.structure.fit_max_relative_error;
  j["vertices"] = result.intrinsic.topology().num_referenced_vertices();
  j["edges"] = result.intrinsic.topology().num_edges;
  j["faces"] = result.intrinsic.topology().num_faces;
  j["setup_seconds"] = result.setup_seconds;
  j["total_seconds"] = result.total_seconds;
  nlohmann::json comps = nlohmann::json::array();
  for (const ComponentFlow& c : result.components) {
    nlohmann::json history = nlohmann::json::array();
    for (const IterationRecord& r : c.flow.history) history.push_back(to_json(r));
    comps.push_back({{"vertices", c.vertices.size()},
                     {"euler_characteristic", c.euler_characteristic},
                     {"genus", c.genus},
                     {"boundary_loops", c.boundary_loops},
                     {"converged", c.flow.converged},
                     {"status", flow_status_name(c.flow.status)},
                     {"message", c.flow.message},
                     {"iterations", c.flow.iterations},
                     {"flipped_edges", c.flow.intrinsic.flips()},
                     {"max_error", c.flow.max_error},
                     {"gauss_bonnet_relative_error", c.flow.gauss_bonnet_relative_error},
                     {"total_area", c.flow.total_area},
                     {"linear_solver", c.flow.linear_solver},
                     {"factorizations", c.flow.factorizations},
                     {"timings", to_json(c.flow.timings)},
                     {"history", history}});
  }
  j["components"] = comps;
  return j;
}

nlohmann::json flow_arrays(const MeshFlowResult& result, const std::vector<int>& file_index) {
  nlohmann::json j;
  j["file_index"] = file_index;
  j["u"] = to_vector(result.u);
  j["curvature"] = to_vector(result.curvature);
  j["target_curvature"] = to_vector(result.target_curvature);
  std::vector<int> fixed(result.target.fixed.begin(), result.target.fixed.end());
  j["fixed"] = fixed;
  const auto& ev = result.intrinsic.topology().edge_vertices;
  nlohmann::json edges = nlohmann::json::array();
  for (int e = 0; e < result.intrinsic.topology().num_edges; ++e)
    edges.push_back({ev(e, 0), ev(e, 1)});
  j["edges"] = edges;
  j["lengths"] = to_vector(result.lengths);
  if (result.intrinsic.flips() > 0) {
    // The edges above belong to the intrinsic Delaunay triangulation; its faces, in mesh
    // vertex indices (face i replaces input face i).
    const Triangles& t = result.intrinsic.topology().triangles;
    nlohmann::json faces = nlohmann::json::array();
    for (Eigen::Index f = 0; f < t.rows(); ++f) faces.push_back({t(f, 0), t(f, 1), t(f, 2)});
    j["triangles"] = faces;
  }
  return j;
}

namespace {

nlohmann::json to_json(const std::complex<double>& z) {
  return {z.real(), z.imag()};
}

nlohmann::json to_json(const SeamTransition& t) {
  return {{"edge", t.edge},
          {"segment", t.segment},
          {"rotation_degrees", t.angle * 180.0 / 3.14159265358979323846},
          {"rotation", to_json(t.rotation)},
          {"translation", to_json(t.translation)},
          {"mismatch", t.mismatch}};
}

nlohmann::json distortion_json(const Distortion& d) {
  return {{"area_distortion_energy", d.area_distortion_energy},
          {"log_area_min", d.log_area_min},
          {"log_area_max", d.log_area_max},
          {"log_area_mean", d.log_area_mean},
          {"log_area_stddev", d.log_area_stddev},
          {"angle_distortion_mean", d.angle_distortion_mean},
          {"angle_distortion_max", d.angle_distortion_max},
          {"flipped_faces", d.flipped_faces},
          {"degenerate_faces", d.degenerate_faces}};
}

}  // namespace

namespace {

/// Per component of a mesh of several: how it was parameterized, its flow and its distortion.
nlohmann::json components_json(const MeshParamResult& r) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t c = 0; c < r.components.size(); ++c) {
    const ComponentParam& comp = r.components[c];
    nlohmann::json j = {{"component", c},
                        {"vertices", comp.vertices.size()},
                        {"faces", comp.faces.size()},
                        {"euler_characteristic", comp.euler_characteristic},
                        {"genus", comp.genus},
                        {"boundary_loops", comp.boundary_loops},
                        {"method", component_method_name(comp.method)},
                        {"parameterized", comp.parameterized},
                        {"message", comp.message},
                        {"cones", comp.cones.size()},
                        {"overlapping_face_pairs", comp.overlapping_face_pairs},
                        {"seam_length", comp.seam_length},
                        {"area_scale", comp.area_scale},
                        {"charts", comp.charts},
                        {"seconds", comp.seconds},
                        {"distortion", distortion_json(comp.distortion)}};
    const MeshFlowResult& flow = comp.param.flow;
    if (comp.method != ComponentMethod::Unfolded && !flow.components.empty()) {
      const FlowResult& f = flow.components.front().flow;
      j["flow"] = {{"converged", f.converged},
                   {"status", flow_status_name(f.status)},
                   {"iterations", f.iterations},
                   {"max_error", f.max_error},
                   {"flipped_edges", f.intrinsic.flips()},
                   {"message", f.message}};
    }
    out.push_back(j);
  }
  return out;
}

nlohmann::json packing_json(const ChartPacking& p) {
  nlohmann::json charts = nlohmann::json::array();
  for (const PackedChart& c : p.charts) {
    charts.push_back({{"faces", c.faces.size()},
                      {"rotation", c.rotation},
                      {"translation", {c.translation.x(), c.translation.y()}},
                      {"box_min", {c.box_min.x(), c.box_min.y()}},
                      {"box_max", {c.box_max.x(), c.box_max.y()}},
                      {"area", c.area}});
  }
  return {{"charts", charts},
          {"scale", p.scale},
          {"gutter", p.gutter},
          {"coverage", p.coverage},
          {"rectangle_coverage", p.rectangle_coverage},
          {"overlapping_face_pairs", p.overlapping_face_pairs},
          {"by_shape", p.by_shape},
          {"raster_work", p.raster_work},
          {"packing_attempts", p.packing_attempts},
          {"seconds", p.seconds}};
}

}  // namespace

nlohmann::json param_report(const MeshParamResult& r, const ParamOptions& options) {
  nlohmann::json j;
  j["converged"] = r.converged;
  j["message"] = r.message;
  j["seconds"] = r.seconds;
  j["cone_mode"] = cone_mode_name(options.cone_mode);
  j["boundary"] = boundary_mode_name(options.boundary);
  j["scheme"] = scheme_name(options.structure.scheme);
  j["quantize"] = options.quantize;
  nlohmann::json cones = nlohmann::json::array();
  for (const Cone& c : r.cones) {
    cones.push_back({{"vertex", c.vertex},
                     {"curvature", c.curvature},
                     {"curvature_over_pi", c.curvature / 3.14159265358979323846}});
  }
  j["cones"] = cones;
  // The one component's automatic cones; an atlas of several has them per component (routes),
  // and prints zeros here as it always has.
  const bool several = !r.components.empty();
  const PipelineDiagnostics one =
      several || r.routes.empty() ? PipelineDiagnostics{} : r.routes.front().pipeline;
  j["cone_selection_max_log_scale"] = one.cone_selection.max_log_scale;
  j["log_scale_spread"] = one.log_scale_spread;
  j["cone_rounds"] = one.cone_rounds;
  j["cone_selection_area_energy"] = one.cone_selection.area_energy;
  // What each seam mode leaves on the seams (the cut's vertices off the cones and the
  // boundary): about the flow's tolerance when rigid, the chosen curvature when free.
  j["seams"] = {{"mode", seam_mode_name(options.seams)},
                {"curvature_vertices", one.seam_curvature.vertices},
                {"curvature_total", one.seam_curvature.total},
                {"curvature_max", one.seam_curvature.max},
                {"choice_seconds", one.seam_curvature.free_seconds},
                {"linear_area_energy", one.seam_curvature.linear_area_energy},
                {"capped_vertices", one.seam_curvature.capped_vertices},
                {"rigid_kept", one.seam_curvature.rigid_kept},
                {"free_area_energy", one.seam_curvature.free_area_energy},
                {"rigid_area_energy", one.seam_curvature.rigid_area_energy}};
  // (Few cones on chi < 0: two candidate sets, the better refined on the flow; said for a mesh
  // of one component also when charts stood in for its exact map.)
  if (r.routes.size() == 1 && r.routes.front().pipeline.cone_refinement.ran) {
    const ConeRefinementReport& c = r.routes.front().pipeline.cone_refinement;
    auto finite = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); };
    j["cone_refinement"] = {{"kept", c.level_cones ? "level" : "selected"},
                            {"selected_area_energy", finite(c.selected_energy)},
                            {"level_area_energy", finite(c.level_energy)},
                            {"refined_area_energy", c.refined_energy},
                            {"steps", c.steps},
                            {"flows", c.flows}};
  }
  nlohmann::json warnings = nlohmann::json::array();
  for (const ComponentRoute& route : r.routes) {
    if (!route.pipeline.too_few_cones.empty()) warnings.push_back(route.pipeline.too_few_cones);
    if (!route.pipeline.free_seams_note.empty()) {
      warnings.push_back(route.pipeline.free_seams_note);
    }
  }
  if (!warnings.empty()) j["warnings"] = warnings;
  j["timings"] = {{"cones", r.timings.cones},       {"flow", r.timings.flow},
                  {"cut", r.timings.cut},           {"development", r.timings.development},
                  {"layout", r.timings.layout},     {"polish", r.timings.polish},
                  {"atlas", r.timings.atlas},       {"distortion", r.timings.distortion},
                  {"untangle", r.timings.untangle}, {"charts", r.timings.charts}};
  j["untangle"] = {{"enabled", options.fold_free.untangle},
                   {"flipped_before", r.untangle.flipped_before},
                   {"flipped_after", r.untangle.flipped_after},
                   {"stuck_faces", r.untangle.stuck_faces},
                   {"moved_vertices", r.untangle.moved_vertices},
                   {"region_faces", r.untangle.region_faces},
                   {"rounds", r.untangle.rounds},
                   {"newton_iterations", r.untangle.newton_iterations},
                   {"seconds", r.untangle.seconds}};
  nlohmann::json routes = nlohmann::json::array();
  for (const ComponentRoute& route : r.routes) {
    routes.push_back({{"method", component_method_name(route.method)},
                      {"charts", route.charts},
                      {"seam_length", route.seam_length},
                      {"flipped_before", route.flipped_before},
                      {"flipped", route.flipped},
                      {"why", route.why}});
  }
  j["routes"] = routes;
  j["polish"] = {{"enabled", options.polish.enabled},
                 {"free_vertices", r.polish.free_vertices},
                 {"moved_vertices", r.polish.moved_vertices},
                 {"sweeps", r.polish.sweeps},
                 {"untangled_faces", r.polish.untangled_faces},
                 {"angle_distortion_face_mean_before", r.polish.angle_distortion_before},
                 {"angle_distortion_face_mean_after", r.polish.angle_distortion_after}};
  j["modification"] = {{"edge_splits", r.edge_splits},
                       {"subdivided", r.subdivided},
                       {"added_vertices", r.added_vertex_parents.size()},
                       {"added_vertex_parents", r.added_vertex_parents},
                       {"output_vertices", r.mesh.num_vertices()}};
  j["flow"] = flow_summary(r.flow, mesh_flow_options(options.structure, options.flow));
  if (several) {
    // The gathered flow has no whole-mesh triangulation: count the mesh parameterized.
    j["flow"]["vertices"] = r.mesh.num_vertices();
    j["flow"]["faces"] = r.mesh.num_faces();
    j["flow"].erase("edges");
    j["components"] = components_json(r);
    j["packing"] = packing_json(r.packing);
  }
  if (!r.converged && !several) return j;
  nlohmann::json segments = nlohmann::json::array();
  for (std::size_t s = 0; s < r.cut.segments.size(); ++s) {
    nlohmann::json seg = {{"vertices", r.cut.segments[s].size()}};
    if (s < r.layout.segment_transitions.size()) {
      seg["transition"] = to_json(r.layout.segment_transitions[s]);
    }
    segments.push_back(seg);
  }
  j["cut"] = {{"generators", r.cut.num_generators},
              {"nodes", r.cut.nodes},
              {"cut_edges", std::count(r.cut.is_cut_edge.begin(), r.cut.is_cut_edge.end(), 1)},
              {"seam_length", r.seam_length},
              {"segments", segments}};
  nlohmann::json lattice = nlohmann::json::array();
  for (const auto& z : r.layout.lattice) lattice.push_back(to_json(z));
  double worst_mismatch = 0;
  for (const SeamTransition& t : r.layout.transitions)
    worst_mismatch = std::max(worst_mismatch, t.mismatch);
  j["layout"] = {{"root_face", r.layout.root_face},
                 {"max_length_relative_error", r.layout.max_length_relative_error},
                 {"max_transition_mismatch", worst_mismatch},
                 {"lattice", lattice},
                 {"uv_scale", r.uv_scale},
                 {"uv_offset", {r.uv_offset[0], r.uv_offset[1]}}};
  nlohmann::json charts = nlohmann::json::array();
  for (const BoundaryChart& c : r.atlas.boundary_charts) {
    charts.push_back({{"segment", c.segment},
                      {"faces", c.faces.size()},
                      {"rotation", to_json(c.rotation)},
                      {"translation", to_json(c.translation)}});
  }
  j["atlas"] = {{"central_chart_faces", r.mesh.num_faces()},
                {"boundary_charts", charts},
                {"max_transition_error", r.atlas.max_transition_error}};
  j["distortion"] = distortion_json(r.distortion);
  j["distortion"]["cones"] = r.cones.size();
  j["distortion"]["seam_length"] = r.seam_length;
  // The faces written: the input's polygons (distortion is measured on their fans as written),
  // or 0 when the triangles are.
  j["polygons"] = r.polygons.num_polygons();
  return j;
}

namespace {

/// A Moebius map of the disk as its matrix entries a and b ([re, im] each).
nlohmann::json to_json(const Mobius& m) {
  return {{"a", {m.a.real(), m.a.imag()}}, {"b", {m.b.real(), m.b.imag()}}};
}

nlohmann::json words_json(const std::vector<SegmentWord>& words) {
  nlohmann::json out = nlohmann::json::array();
  for (const SegmentWord& w : words) {
    nlohmann::json word = nlohmann::json::array();
    for (const auto& [segment, sign] : w) word.push_back({segment, sign});
    out.push_back(word);
  }
  return out;
}

}  // namespace

nlohmann::json refinement_report(const CommonRefinement& c, const Parameterization& p) {
  return {{"vertices", c.positions.rows()},
          {"triangles", c.triangles.rows()},
          {"texture_coordinates", c.uv.rows()},
          {"input_vertices", p.mesh.num_vertices()},
          {"input_faces", p.mesh.num_faces()},
          {"isometric_flips", c.isometric_flips},
          {"ptolemy_flips", c.ptolemy_flips},
          {"points",
           {{"input_x_delaunay", c.input_delaunay_points},
            {"delaunay_x_intrinsic", c.delaunay_intrinsic_points},
            {"input_x_intrinsic", c.interior_points}}},
          {"max_intrinsic_length_error", c.max_intrinsic_length_error},
          {"max_corner_mismatch", c.max_corner_mismatch},
          {"max_metric_mismatch", c.max_metric_mismatch},
          {"max_development_error", c.max_development_error},
          {"degenerate_triangles", c.degenerate_triangles},
          {"inverted_triangles", c.inverted_triangles},
          {"order_repairs", c.order_repairs},
          {"seconds", c.seconds}};
}

nlohmann::json hyperbolic_param_report(const HyperbolicParamResult& r,
                                       const HyperbolicParamOptions& options) {
  nlohmann::json j;
  j["geometry"] = "hyperbolic";
  j["converged"] = r.converged;
  j["message"] = r.message;
  j["seconds"] = r.seconds;
  StructureOptions structure = options.structure;
  structure.geometry = Geometry::Hyperbolic;
  j["flow"] = flow_summary(r.flow, mesh_flow_options(structure, options.flow));
  if (!r.converged) return j;
  nlohmann::json segments = nlohmann::json::array();
  for (const SegmentIsometry& s : r.layout.segment_maps) {
    segments.push_back({{"vertices", r.cut.segments[s.segment].size()},
                        {"map", to_json(s.map)},
                        {"translation_length", s.translation_length},
                        {"mismatch", s.mismatch}});
  }
  j["cut"] = {{"generators", r.cut.num_generators},
              {"nodes", r.cut.nodes},
              {"cut_edges", std::count(r.cut.is_cut_edge.begin(), r.cut.is_cut_edge.end(), 1)},
              {"seam_length", r.seam_length},
              {"segments", segments},
              {"node_words", words_json(r.layout.node_words)}};
  j["layout"] = {{"root_face", r.layout.root_face},
                 {"max_length_relative_error", r.layout.max_length_relative_error},
                 {"flipped_faces", r.layout.num_flipped_faces},
                 {"max_radius", r.layout.max_radius},
                 {"development_length_mismatch", r.development_length_mismatch}};
  if (!r.group_failure.empty()) j["fuchsian_group_failure"] = r.group_failure;
  if (r.has_group) {
    const FuchsianGroup& g = r.group;
    nlohmann::json a = nlohmann::json::array(), b = nlohmann::json::array();
    for (int i = 0; i < g.genus; ++i) {
      a.push_back({{"map", to_json(g.a[i])}, {"translation_length", translation_length(g.a[i])}});
      b.push_back({{"map", to_json(g.b[i])}, {"translation_length", translation_length(g.b[i])}});
    }
    j["fuchsian_group"] = {{"genus", g.genus},
                           {"a", a},
                           {"b", b},
                           {"a_words", words_json(g.a_words)},
                           {"b_words", words_json(g.b_words)},
                           {"relation_residual", g.relation_residual},
                           {"node_residual", g.node_residual}};
  }
  j["distortion"] = distortion_json(r.distortion);
  j["polygons"] = r.polygons.num_polygons();
  return j;
}

nlohmann::json sphere_report(const SphereResult& r, const SphereOptions& options) {
  nlohmann::json j;
  j["converged"] = r.converged;
  j["valid"] = r.valid;
  j["message"] = r.message;
  j["seconds"] = r.seconds;
  j["scheme"] = scheme_name(options.structure.scheme);
  j["pole"] = r.pole;
  j["poles_tried"] = r.poles_tried;
  TargetSpec disk;
  disk.boundary = BoundaryMode::DiskLength;
  j["flow"] = flow_summary(r.flow, mesh_flow_options(options.structure, options.flow, disk));
  j["timings"] = {{"flow", r.flow_seconds},
                  {"layout", r.layout_seconds},
                  {"normalisation", r.normalisation_seconds},
                  {"total", r.seconds}};
  if (r.positions.rows() == 0) return j;
  j["disk"] = {{"layout_length_error", r.layout_length_error},
               {"boundary_circle_deviation", r.boundary_circle_deviation},
               {"inverted_pole_faces", r.inverted_pole_faces},
               {"reversed_faces", r.reversed_disk_faces}};
  j["precision"] = {{"bits", r.precision_bits},
                    {"min_plane_altitude", r.min_plane_altitude},
                    {"min_sphere_altitude", r.min_sphere_altitude},
                    {"unresolved_faces", r.unresolved_faces}};
  j["normalisation"] = {{"iterations", r.centre_iterations},
                        {"initial_centre", r.initial_centre},
                        {"centre_of_mass", r.centre_of_mass},
                        {"max_boost_norm", r.max_boost_norm}};
  j["untangle"] = {{"enabled", options.untangle},
                   {"vertices", r.untangled_vertices},
                   {"max_move", r.max_untangle_move},
                   {"max_relative_move", r.max_untangle_relative_move}};
  j["invariants"] = {{"max_radius_deviation", r.max_radius_deviation},
                     {"inverted_faces", r.inverted_faces},
                     {"inverted_by_rounding", r.inverted_by_rounding},
                     {"spherical_area", r.spherical_area},
                     {"spherical_area_error", r.spherical_area - 4 * 3.14159265358979323846}};
  j["distortion"] = {{"angle_distortion_mean", r.angle_distortion_mean},
                     {"angle_distortion_p95", r.angle_distortion_p95},
                     {"angle_distortion_max", r.angle_distortion_max},
                     {"angle_error_mean", r.angle_error_mean},
                     {"angle_error_max", r.angle_error_max},
                     {"log_area_min", r.log_area_min},
                     {"log_area_max", r.log_area_max},
                     {"log_area_mean", r.log_area_mean},
                     {"log_area_stddev", r.log_area_stddev}};
  return j;
}

nlohmann::json spline_report(const SplineResult& r, const SplineOptions& options) {
  nlohmann::json j;
  j["converged"] = r.converged;
  if (!r.converged) j["message"] = r.message;
  j["smoothness"] = options.smoothness;
  j["refine"] = options.refine;
  if (!r.converged) return j;
  j["param"] = param_report(r.param, options.param);
  if (!r.parameterization_note.empty()) j["parameterization_note"] = r.parameterization_note;
  j["error"] = {
      {"bbox_diagonal", r.error.bbox_diagonal},   {"max_parametric", r.error.max_parametric},
      {"rms_parametric", r.error.rms_parametric}, {"max_distance", r.error.max_distance},
      {"rms_distance", r.error.rms_distance},     {"samples", r.error.samples}};
  const ContinuityReport& c = r.continuity;
  j["continuity"] = {{"edges_checked", c.edges_checked},
                     {"samples", c.samples},
                     {"max_value_jump", c.max_value_jump},
                     {"max_gradient_jump", c.max_gradient_jump},
                     {"relative_value_jump", c.relative_value_jump},
                     {"relative_gradient_jump", c.relative_gradient_jump},
                     {"frame_closure_error", r.domain.frame_closure_error}};
  j["fit"] = {{"weight", r.fit.weight},
              {"data_energy", r.fit.data_energy},
              {"smoothness_energy", r.fit.smoothness_energy},
              {"solve_residual", r.fit.solve_residual},
              {"unknowns", r.fit.num_unknowns},
              {"regularized", r.fit.regularized},
              {"solver", r.fit.solver}};
  j["surface"] = {{"vertices", r.surface.num_vertices()}, {"faces", r.surface.num_faces()}};
  j["control_net"] = {{"vertices", r.control_net.num_vertices()},
                      {"faces", r.control_net.num_faces()}};
  j["seconds"] = {{"param", r.seconds_param},
                  {"fit", r.seconds_fit},
                  {"evaluate", r.seconds_evaluate},
                  {"error", r.seconds_error},
                  {"total", r.seconds}};
  return j;
}

}  // namespace ricci::cli
