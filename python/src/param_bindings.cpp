/// \file
/// Bindings of the param module: cone selection, cut graph, layout, atlas, distortion and the
/// parameterize pipeline.

#include "bindings.hpp"
#include "ricci/mesh/validate.hpp"
#include "ricci/param/parameterize.hpp"
#include "ricci/param/refinement/common_refinement.hpp"

namespace ricci::python {

void bind_param(py::module_& m) {
  py::enum_<ConeMode> cone_mode(m, "ConeMode", "Where the cones come from.");
  cone_mode.value("Needed", ConeMode::Needed)
      .value("None_", ConeMode::None)
      .value("User", ConeMode::User)
      .value("Auto", ConeMode::Auto)
      .value("OneCone", ConeMode::OneCone);
  cone_mode.def(py::init([](const std::string& name) { return parse_cone_mode(name); }),
                py::arg("name"));
  bind_enum_names(cone_mode);
  m.def("cone_mode_name", &cone_mode_name, py::arg("mode"));

  py::enum_<SeamMode> seam_mode(m, "SeamMode",
                                "How a seam's two copies relate: Rigid (the flat metric with "
                                "cones) or Free (one length, any rotation).");
  seam_mode.value("Rigid", SeamMode::Rigid).value("Free", SeamMode::Free);
  seam_mode.def(py::init([](const std::string& name) { return parse_seam_mode(name); }),
                py::arg("name"));
  bind_enum_names(seam_mode);
  m.def("seam_mode_name", &seam_mode_name, py::arg("mode"));

  StructBinding<FreeSeamOptions>(m, "FreeSeamOptions", "How SeamMode.Free chooses the seams.")
      .field("smoothness", &FreeSeamOptions::smoothness,
             "weight of the Dirichlet energy of the log scale per face (1000)")
      .field("selection_smoothness", &FreeSeamOptions::selection_smoothness,
             "weight of the free curvatures' squares per face while cones are chosen (3)")
      .repr();
  StructBinding<ConeRefinementReport>(
      m, "ConeRefinementReport",
      "Few cones on chi < 0: two candidate cone sets measured on the flow, the better refined.")
      .readonly("ran", &ConeRefinementReport::ran, "the count was too few for the bounds")
      .readonly("level_cones", &ConeRefinementReport::level_cones, "the level cones were kept")
      .readonly("selected_energy", &ConeRefinementReport::selected_energy,
                "E of the bounded selection's cones")
      .readonly("level_energy", &ConeRefinementReport::level_energy, "E of the level cones")
      .readonly("refined_energy", &ConeRefinementReport::refined_energy, "E after refinement")
      .readonly("steps", &ConeRefinementReport::steps, "quasi-Newton steps")
      .readonly("flows", &ConeRefinementReport::flows, "flows run")
      .repr();

  StructBinding<SeamCurvature>(m, "SeamCurvature", "Curvature on the seams, off the cones.")
      .readonly("vertices", &SeamCurvature::vertices, "cut vertices that are not cones")
      .readonly("total", &SeamCurvature::total, "sum of |K| over them")
      .readonly("max", &SeamCurvature::max, "largest |K| among them")
      .readonly("free_seconds", &SeamCurvature::free_seconds, "Free: time to choose it")
      .readonly("linear_area_energy", &SeamCurvature::linear_area_energy,
                "Free: E of the linearised choice")
      .readonly("capped_vertices", &SeamCurvature::capped_vertices,
                "Free: vertices whose chosen curvature was held at 1.75 pi")
      .readonly("rigid_kept", &SeamCurvature::rigid_kept,
                "Free: the rigid map, made because the free one was in doubt, distorted less "
                "and is the result")
      .readonly("free_area_energy", &SeamCurvature::free_area_energy,
                "Free, when the rigid map was made: the free map's E")
      .readonly("rigid_area_energy", &SeamCurvature::rigid_area_energy,
                "Free, when the rigid map was made: the rigid map's E")
      .repr();

  StructBinding<ParamTimings>(m, "ParamTimings", "Wall time of each stage of parameterize.")
      .readonly("cones", &ParamTimings::cones, "")
      .readonly("flow", &ParamTimings::flow, "")
      .readonly("cut", &ParamTimings::cut, "")
      .readonly("development", &ParamTimings::development, "")
      .readonly("layout", &ParamTimings::layout, "")
      .readonly("polish", &ParamTimings::polish, "")
      .readonly("atlas", &ParamTimings::atlas, "")
      .readonly("distortion", &ParamTimings::distortion, "")
      .repr();

  StructBinding<ConeSelectionOptions>(m, "ConeSelectionOptions", "Options of select_cones.")
      .field("count", &ConeSelectionOptions::count,
             "place exactly this many cones; 0: as many as max_log_scale needs")
      .field("max_log_scale", &ConeSelectionOptions::max_log_scale,
             "add cones until max |u - mean u| of the linearised flat metric is at most this")
      .field("max_cones", &ConeSelectionOptions::max_cones, "never more than this many; 0: no cap")
      .field("max_face_angle", &ConeSelectionOptions::max_face_angle,
             "largest average uv corner angle a cone may ask of its faces (radians)")
      .field("max_corner_angle", &ConeSelectionOptions::max_corner_angle,
             "largest uv corner angle at a cone, estimated from the input's (radians)")
      .field("max_curvature", &ConeSelectionOptions::max_curvature,
             "largest curvature of a cone (radians)")
      .field("quantize", &ConeSelectionOptions::quantize,
             "curvatures in multiples of pi/2, chosen in the model (ParamOptions.quantize sets "
             "it)")
      .field("smoothness", &ConeSelectionOptions::smoothness,
             "weight of angle against area distortion: curvatures minimise log(1 + E) + "
             "smoothness D / #F (D: Dirichlet energy of the log scale)")
      .field("try_first_cone_candidates", &ConeSelectionOptions::try_first_cone_candidates,
             "well-spread candidates tried for the first cone of a closed surface")
      .enum_field("boundary", &ConeSelectionOptions::boundary, &parse_boundary_mode,
                  "BoundaryMode while cones are chosen (parameterize sets it from its own)")
      .field("structure", &ConeSelectionOptions::structure,
             "StructureOptions (parameterize sets it from its own)")
      .keyword_constructor()
      .repr();

  StructBinding<ConeSelection>(m, "ConeSelection", "What select_cones returns.")
      .readonly("vertices", &ConeSelection::vertices, "cone vertices in the order chosen")
      .readonly("max_log_scale", &ConeSelection::max_log_scale, "after each addition")
      .readonly("linear_curvature", &ConeSelection::linear_curvature,
                "curvature of each cone: the bounded least-squares minimiser of the log-scale "
                "spread")
      .readonly("log_scale_rms", &ConeSelection::log_scale_rms, "at the end")
      .readonly("within_bounds", &ConeSelection::within_bounds,
                "every cone within what its faces can draw")
      .repr();

  StructBinding<ChartPackingOptions>(m, "ChartPackingOptions", "Options of pack_charts.")
      .field("gutter", &ChartPackingOptions::gutter,
             "space between the charts' rectangles in uv units (half of it to the edge)")
      .field("rotate", &ChartPackingOptions::rotate,
             "turn charts to their minimal-area rectangle (and quarter turns)")
      .field("scale_tolerance", &ChartPackingOptions::scale_tolerance,
             "relative precision of the common scale's search")
      .field("raster_resolution", &ChartPackingOptions::raster_resolution,
             "also pack by shape on a grid of about this many cells across (0: rectangles only)")
      .field("raster_work_limit", &ChartPackingOptions::raster_work_limit,
             "work (grid rows and positions tried) after which the shape search stops")
      .keyword_constructor()
      .repr();

  StructBinding<PackedChart>(m, "PackedChart",
                             "A placed chart: uv = scale R(rotation) layout + translation.")
      .readonly("faces", &PackedChart::faces, "its faces")
      .readonly("rotation", &PackedChart::rotation, "radians, counter-clockwise")
      .readonly("translation", &PackedChart::translation, "")
      .readonly("box_min", &PackedChart::box_min, "bounding box of its uv")
      .readonly("box_max", &PackedChart::box_max, "")
      .readonly("area", &PackedChart::area, "uv area of its faces")
      .repr();

  StructBinding<ChartPacking>(m, "ChartPacking", "What pack_charts returns.")
      .readonly("uv", &ChartPacking::uv,
                "#V by 2 in [0, 1]^2 (empty in MeshParamResult.packing: moved into its uv)")
      .readonly("face_chart", &ChartPacking::face_chart, "#F chart of each face")
      .readonly("charts", &ChartPacking::charts, "list of PackedChart")
      .readonly("scale", &ChartPacking::scale, "the common scale (uv units per layout unit)")
      .readonly("gutter", &ChartPacking::gutter, "gutter used")
      .readonly("coverage", &ChartPacking::coverage, "uv area of the faces / area of the square")
      .readonly("rectangle_coverage", &ChartPacking::rectangle_coverage,
                "area of the charts' bounding rectangles / area of the square")
      .readonly("overlapping_face_pairs", &ChartPacking::overlapping_face_pairs,
                "pairs of faces of different charts overlapping (0)")
      .readonly("by_shape", &ChartPacking::by_shape,
                "placed by shape on the grid (else in their rectangles)")
      .readonly("raster_work", &ChartPacking::raster_work, "work the shape search did")
      .readonly("packing_attempts", &ChartPacking::packing_attempts, "")
      .readonly("seconds", &ChartPacking::seconds, "")
      .repr();

  m.def("pack_charts", &pack_charts, py::arg("layout"), py::arg("triangles"),
        py::arg("face_chart") = std::vector<int>{}, py::arg("options") = ChartPackingOptions{},
        "Packs the charts of a layout (#V by 2, any units) into the unit square: each turned "
        "to its minimal-area rectangle, one common scale, no overlap. face_chart: chart per "
        "face, or empty for the connected pieces.");

  StructBinding<UvOverlaps>(m, "UvOverlaps", "What find_uv_overlaps returns.")
      .readonly("count", &UvOverlaps::count, "overlapping pairs")
      .readonly("pairs", &UvOverlaps::pairs, "the first max_pairs of them (face indices)")
      .repr();
  m.def("find_uv_overlaps", &find_uv_overlaps, py::arg("uv"), py::arg("triangles"),
        py::arg("face_group") = std::vector<int>{}, py::arg("max_pairs") = 16,
        "Pairs of faces whose uv triangles' interiors intersect, decided exactly; with "
        "face_group only pairs of different groups.");

  StructBinding<PolishOptions>(m, "PolishOptions", "Options of polish_angles.")
      .field("enabled", &PolishOptions::enabled,
             "run the angle polish (False: the discrete conformal map itself)")
      .field("max_sweeps", &PolishOptions::max_sweeps, "sweeps over the free vertices at most")
      .field("tolerance", &PolishOptions::tolerance,
             "stop when a sweep lowers the mean ratio's excess over 1 by less than this fraction")
      .keyword_constructor()
      .repr();

  StructBinding<PolishResult>(m, "PolishResult", "What polish_angles did.")
      .readonly("uv", &PolishResult::uv,
                "polish_angles: the polished positions; ParamResult.polish: the layout's "
                "positions before the polish (empty when it did not run)")
      .readonly("free_vertices", &PolishResult::free_vertices,
                "vertices it may move (on no seam, no boundary, no bad face)")
      .readonly("moved_vertices", &PolishResult::moved_vertices, "")
      .readonly("sweeps", &PolishResult::sweeps, "")
      .readonly("untangled_faces", &PolishResult::untangled_faces,
                "faces drawn flipped that were unflipped by moving a free vertex")
      .readonly("angle_distortion_before", &PolishResult::angle_distortion_before,
                "unweighted face mean of sigma_max / sigma_min")
      .readonly("angle_distortion_after", &PolishResult::angle_distortion_after, "")
      .readonly("seconds", &PolishResult::seconds, "")
      .repr();

  m.def("polish_angles", &polish_angles, py::arg("mesh"), py::arg("uv_triangles"), py::arg("uv"),
        py::arg("options") = PolishOptions{},
        "Moves the layout's vertices on no seam and no boundary to lower the faces' mean "
        "sigma_max / sigma_min, keeping seams, cones and boundary exact; returns PolishResult.");

  StructBinding<FoldFreeOptions>(m, "FoldFreeOptions",
                                 "What parameterize does where the exact map fails its checks.")
      .field("untangle", &FoldFreeOptions::untangle,
             "untangle flipped faces, seams, cones and boundary kept exact")
      .field("charts", &FoldFreeOptions::charts,
             "lay out a component whose exact map still fails as charts with free boundary")
      .field("max_length_error", &FoldFreeOptions::max_length_error,
             "largest relative edge length error of a layout that closes up")
      .keyword_constructor()
      .repr();

  StructBinding<UntangleResult>(m, "UntangleResult", "What untangle_layout did.")
      .readonly("flipped_before", &UntangleResult::flipped_before, "")
      .readonly("flipped_after", &UntangleResult::flipped_after, "")
      .readonly("stuck_faces", &UntangleResult::stuck_faces,
                "flipped faces none of whose vertices may move")
      .readonly("moved_vertices", &UntangleResult::moved_vertices, "")
      .readonly("region_faces", &UntangleResult::region_faces, "")
      .readonly("rounds", &UntangleResult::rounds, "")
      .readonly("newton_iterations", &UntangleResult::newton_iterations, "")
      .readonly("seconds", &UntangleResult::seconds, "")
      .repr();

  StructBinding<ParamOptions>(m, "ParamOptions", "Options of parameterize.")
      .enum_field("cone_mode", &ParamOptions::cone_mode, &parse_cone_mode,
                  "ConeMode (or 'none', 'user', 'auto', 'one')")
      .field("cones", &ParamOptions::cones, "ConeMode.User: list of Cone (input vertex indices)")
      .field("auto_cones", &ParamOptions::auto_cones, "ConeSelectionOptions for ConeMode.Auto")
      .field("quantize", &ParamOptions::quantize, "round cone curvatures to multiples of pi/2")
      .enum_field("boundary", &ParamOptions::boundary, &parse_boundary_mode,
                  "BoundaryMode (or 'free', 'disk', 'disk-length')")
      .enum_field("seams", &ParamOptions::seams, &parse_seam_mode, "SeamMode (or 'rigid', 'free')")
      .field("free_seams", &ParamOptions::free_seams,
             "FreeSeamOptions: how SeamMode.Free chooses the seams' curvature")
      .field("structure", &ParamOptions::structure, "StructureOptions: the discrete metric")
      .field("flow", &ParamOptions::flow, "FlowOptions (tolerance 1e-12 by default)")
      .field("modify_connectivity", &ParamOptions::modify_connectivity,
             "split edges around cones whose valence breaks the single-vertex bound")
      .field("packing", &ParamOptions::packing,
             "ChartPackingOptions: several components, how their charts are packed")
      .field("polish", &ParamOptions::polish,
             "PolishOptions: the angle polish of the layout's interior (enabled by default)")
      .field("polygons", &ParamOptions::polygons,
             "Polygons (read_mesh's info.polygons): faces whose diagonals are never cut")
      .field("fold_free", &ParamOptions::fold_free,
             "FoldFreeOptions: untangling, and charts where the exact map fails")
      .keyword_constructor()
      .repr();

  StructBinding<CutGraph>(m, "CutGraph", "A cut graph: slicing along it leaves a disk.")
      .flags("is_cut_edge", &CutGraph::is_cut_edge, "#E bools")
      .readonly("num_generators", &CutGraph::num_generators, "homology generators (2 g)")
      .readonly("nodes", &CutGraph::nodes, "cut vertices of cut degree != 2, and the cones")
      .readonly("segments", &CutGraph::segments, "vertex paths from node to node")
      .readonly("length", &CutGraph::length, "total length of the cut edges")
      .repr();

  StructBinding<CutMesh>(m, "CutMesh", "The mesh sliced open along a cut.")
      .readonly("triangles", &CutMesh::triangles, "#F by 3, new vertex indices")
      .readonly("to_original", &CutMesh::to_original, "per new vertex: the vertex it copies")
      .readonly("topology", &CutMesh::topology, "Topology of the sliced mesh")
      .repr();

  StructBinding<SeamTransition>(m, "SeamTransition",
                                "Rigid motion z -> rotation z + translation across a cut edge.")
      .readonly("edge", &SeamTransition::edge, "")
      .readonly("segment", &SeamTransition::segment, "")
      .readonly("rotation", &SeamTransition::rotation, "unit complex number")
      .readonly("translation", &SeamTransition::translation, "complex")
      .readonly("angle", &SeamTransition::angle, "arg(rotation), radians")
      .readonly("mismatch", &SeamTransition::mismatch, "relative to the edge length")
      .repr();

  StructBinding<Layout>(m, "Layout", "Planar layout of a flat metric (metric units).")
      .readonly("uv", &Layout::uv, "#V_cut by 2 positions")
      .readonly("root_face", &Layout::root_face, "")
      .readonly("max_length_relative_error", &Layout::max_length_relative_error,
                "how well the layout reproduces the metric's lengths")
      .readonly("num_flipped_faces", &Layout::num_flipped_faces, "")
      .readonly("transitions", &Layout::transitions, "SeamTransition per interior cut edge")
      .readonly("segment_transitions", &Layout::segment_transitions, "per cut segment")
      .readonly("lattice", &Layout::lattice, "flat torus: reduced lattice basis (complex)")
      .repr();

  StructBinding<BoundaryChart>(m, "BoundaryChart", "A chart around one cut segment.")
      .readonly("segment", &BoundaryChart::segment, "")
      .readonly("faces", &BoundaryChart::faces, "faces of the original mesh")
      .readonly("corner_uv", &BoundaryChart::corner_uv, "len(faces) by 6: u0 v0 u1 v1 u2 v2")
      .flags("side", &BoundaryChart::side, "per chart face: True on side B")
      .readonly("rotation", &BoundaryChart::rotation, "")
      .readonly("translation", &BoundaryChart::translation, "")
      .readonly("max_gap", &BoundaryChart::max_gap, "")
      .repr();

  StructBinding<AffineAtlas>(m, "AffineAtlas", "Central chart plus one chart per cut segment.")
      .readonly("boundary_charts", &AffineAtlas::boundary_charts, "")
      .readonly("max_transition_error", &AffineAtlas::max_transition_error, "")
      .repr();

  StructBinding<Distortion>(m, "Distortion", "Distortion figures of a parameterization.")
      .readonly("area_distortion_energy", &Distortion::area_distortion_energy,
                "the tutorial's eq. 9")
      .readonly("log_area_min", &Distortion::log_area_min, "")
      .readonly("log_area_max", &Distortion::log_area_max, "")
      .readonly("log_area_mean", &Distortion::log_area_mean, "")
      .readonly("log_area_stddev", &Distortion::log_area_stddev, "")
      .readonly("angle_distortion_mean", &Distortion::angle_distortion_mean,
                "sigma_max / sigma_min, area-weighted mean")
      .readonly("angle_distortion_max", &Distortion::angle_distortion_max, "")
      .readonly("flipped_faces", &Distortion::flipped_faces, "")
      .readonly("degenerate_faces", &Distortion::degenerate_faces, "")
      .readonly("surface_area", &Distortion::surface_area, "")
      .readonly("layout_area", &Distortion::layout_area, "")
      .repr();
  m.def("measure_distortion", &measure_distortion, py::arg("mesh"), py::arg("uv_triangles"),
        py::arg("uv"), "Measures a layout (uv_triangles index uv per corner) against the mesh.");

  StructBinding<Parameterization> parameterization(
      m, "Parameterization",
      "A parameterization: mesh, cut, layout, uv and what the flow did; the fields "
      "ParamResult (one component) and MeshParamResult (the whole mesh) share.");
  parameterization
      .readonly("converged", &Parameterization::converged,
                "the flow reached its tolerance (whole mesh: every component parameterized)")
      .computed(
          "message",
          [](const Parameterization& r) { return message_with_fixes(r.message, r.flow.fixes); },
          "why not, when it did not (with the keywords that may help)")
      .computed(
          "vertices", [](const Parameterization& r) { return r.mesh.positions; },
          "#V by 3 positions of the mesh parameterized (mesh.positions)")
      .computed(
          "triangles", [](const Parameterization& r) { return r.mesh.triangles; },
          "#F by 3 triangles of the mesh parameterized (mesh.triangles)")
      .readonly("uv", &Parameterization::uv, "#UV by 2 texture coordinates in the unit square")
      .computed(
          "uv_triangles", [](const Parameterization& r) { return r.cut_mesh.triangles; },
          "#F by 3 indices into uv per corner (cut_mesh.triangles)")
      .readonly("mesh", &Parameterization::mesh,
                "input vertices first, then vertices added by edge splits")
      .readonly("vertex_origin", &Parameterization::vertex_origin,
                "per vertex: input vertex, or -1 when added")
      .readonly("added_vertex_parents", &Parameterization::added_vertex_parents,
                "per added vertex: the edge it splits")
      .readonly("edge_splits", &Parameterization::edge_splits, "")
      .readonly("subdivided", &Parameterization::subdivided, "the mesh was subdivided once")
      .readonly("cones", &Parameterization::cones, "final Cone list (output vertex indices)")
      .computed(
          "layout_error",
          [](const Parameterization& r) { return r.layout.max_length_relative_error; },
          "layout.max_length_relative_error")
      .computed(
          "lattice", [](const Parameterization& r) { return r.layout.lattice; },
          "layout.lattice: flat torus lattice basis as complex numbers (metric units)")
      .readonly("distortion", &Parameterization::distortion,
                "Distortion of the faces written (with polygons: their fans as written)")
      .readonly("polygons", &Parameterization::polygons,
                "Polygons to write (options.polygons, each from a corner whose fan is sound); "
                "empty without polygons")
      .readonly("seam_length", &Parameterization::seam_length, "3D length of the cut edges")
      .readonly("uv_scale", &Parameterization::uv_scale, "uv = (layout - offset) * uv_scale")
      .readonly("uv_offset", &Parameterization::uv_offset, "")
      .readonly("flow", &Parameterization::flow, "MeshFlowResult")
      .readonly("cut", &Parameterization::cut, "CutGraph")
      .readonly("cut_mesh", &Parameterization::cut_mesh, "CutMesh")
      .readonly("layout", &Parameterization::layout, "Layout")
      .readonly("polish", &Parameterization::polish,
                "PolishResult (its uv: the layout before the polish)")
      .readonly("atlas", &Parameterization::atlas, "AffineAtlas")
      .readonly("seconds", &Parameterization::seconds, "")
      .readonly("timings", &Parameterization::timings, "ParamTimings: seconds per stage")
      .readonly("untangle", &Parameterization::untangle, "UntangleResult of the exact map's layout")
      .repr();

  StructBinding<PipelineDiagnostics> pipeline_diagnostics(
      m, "PipelineDiagnostics",
      "What the one-component pipeline measured beyond the map: automatic cones, development.");
  pipeline_diagnostics
      .readonly("cone_selection", &PipelineDiagnostics::cone_selection,
                "ConeSelection (last round)")
      .readonly("log_scale_spread", &PipelineDiagnostics::log_scale_spread,
                "automatic cones: max |u - mean u| of the flat metric away from the cones")
      .readonly("cone_rounds", &PipelineDiagnostics::cone_rounds,
                "automatic cones: times they were chosen again, with more of them")
      .readonly("development_length_mismatch", &PipelineDiagnostics::development_length_mismatch,
                "how well the input faces developed in the flat metric agree on their edges")
      .readonly("cone_refinement", &PipelineDiagnostics::cone_refinement,
                "ConeRefinementReport: few cones on chi < 0 refined on the flow")
      .readonly("seam_curvature", &PipelineDiagnostics::seam_curvature,
                "SeamCurvature: what the seams carry (about 0 with rigid seams)")
      .readonly("too_few_cones", &PipelineDiagnostics::too_few_cones,
                "rigid seams on genus >= 1: the cones asked for are too few (empty otherwise)")
      .readonly("free_seams_note", &PipelineDiagnostics::free_seams_note,
                "free seams that gave way to the rigid map, or whose map distorts strongly "
                "(empty otherwise)")
      .repr();

  StructBinding<ParamResult, Parameterization, PipelineDiagnostics>(
      m, "ParamResult",
      "One component parameterized by one route (ComponentParam.param): a Parameterization "
      "with its PipelineDiagnostics.",
      parameterization, pipeline_diagnostics)
      .repr();

  StructBinding<MeshParamResult, Parameterization>(
      m, "MeshParamResult",
      "What parameterize returns: the whole mesh's Parameterization, the routes (each with its "
      "PipelineDiagnostics), and the components gathered into the atlas.",
      parameterization)
      .readonly("routes", &MeshParamResult::routes,
                "ComponentRoute per component: the route its layout took")
      .readonly("components", &MeshParamResult::components,
                "a ComponentParam per component when the atlas was gathered from them (several, "
                "or one whose exact map gave way); empty otherwise")
      .readonly("packing", &MeshParamResult::packing, "with components: ChartPacking")
      .repr();

  py::enum_<ComponentMethod> component_method(
      m, "ComponentMethod", "How a component of a mesh of several was parameterized.");
  component_method.value("Flow", ComponentMethod::Flow)
      .value("Untangled", ComponentMethod::Untangled)
      .value("Charts", ComponentMethod::Charts)
      .value("Unfolded", ComponentMethod::Unfolded)
      .value("Patches", ComponentMethod::Patches);
  bind_enum_names(component_method);
  m.def("component_method_name", &component_method_name, py::arg("method"));

  StructBinding<ComponentRoute>(m, "ComponentRoute",
                                "The route one component's layout took (MeshParamResult.routes).")
      .readonly("method", &ComponentRoute::method, "ComponentMethod")
      .readonly("charts", &ComponentRoute::charts, "charts of its layout in the atlas")
      .readonly("seam_length", &ComponentRoute::seam_length, "3D length of its seams")
      .readonly("flipped_before", &ComponentRoute::flipped_before,
                "faces the exact map drew flipped, before untangling")
      .readonly("flipped", &ComponentRoute::flipped, "faces flipped in its final layout")
      .readonly("why", &ComponentRoute::why, "why the exact map gave way (empty when it served)")
      .readonly("pipeline", &ComponentRoute::pipeline,
                "PipelineDiagnostics of the map that served (defaults for charts, unfoldings)")
      .repr();

  StructBinding<ComponentParam>(
      m, "ComponentParam", "One component on its way into the atlas (MeshParamResult.components).")
      .readonly("vertices", &ComponentParam::vertices, "input vertices of the component")
      .readonly("faces", &ComponentParam::faces, "input faces of the component")
      .readonly("euler_characteristic", &ComponentParam::euler_characteristic, "")
      .readonly("genus", &ComponentParam::genus, "")
      .readonly("boundary_loops", &ComponentParam::boundary_loops, "")
      .readonly("method", &ComponentParam::method, "ComponentMethod")
      .readonly("parameterized", &ComponentParam::parameterized,
                "in one chart: by the flow or unfolded (False: Patches)")
      .readonly("message", &ComponentParam::message, "why the pipeline failed")
      .readonly("cones", &ComponentParam::cones, "its cones (vertices of MeshParamResult.mesh)")
      .readonly("distortion", &ComponentParam::distortion, "of its part of the atlas")
      .readonly("overlapping_face_pairs", &ComponentParam::overlapping_face_pairs,
                "pairs of its own faces overlapping in uv")
      .readonly("seam_length", &ComponentParam::seam_length, "")
      .readonly("area_scale", &ComponentParam::area_scale,
                "its layout scaled by this to its 3D area before packing")
      .readonly("charts", &ComponentParam::charts, "its charts in MeshParamResult.packing.charts")
      .readonly("vertex_map", &ComponentParam::vertex_map,
                "per vertex of param.mesh: vertex of MeshParamResult.mesh")
      .readonly("face_map", &ComponentParam::face_map,
                "per face of param.mesh: face of MeshParamResult.mesh")
      .readonly("cut_vertex_offset", &ComponentParam::cut_vertex_offset,
                "first of its vertices in MeshParamResult.cut_mesh")
      .readonly("seconds", &ComponentParam::seconds, "")
      .readonly("param", &ComponentParam::param, "ParamResult of the component alone")
      .repr();

  m.def(
      "parameterize",
      [](const Mesh& mesh, ParamOptions options) {
        validate_mesh(mesh, "parameterize");
        return run_without_gil<MeshParamResult>(options.flow,
                                                [&] { return parameterize(mesh, options); });
      },
      py::arg("mesh"), py::arg("options") = ParamOptions{},
      "Global conformal parameterization of a manifold mesh (validated first); several "
      "components are parameterized one by one and packed into one atlas. Raises "
      "InvalidInput, TopologyError.");

  StructBinding<CommonRefinementOptions>(m, "CommonRefinementOptions",
                                         "Options of common_refinement.")
      .field("interpolation_matrix", &CommonRefinementOptions::interpolation_matrix,
             "build the interpolation matrix (interpolation_triplets)")
      .keyword_constructor()
      .repr();

  StructBinding<CommonRefinement>(
      m, "CommonRefinement",
      "The common refinement of the input, its intrinsic Delaunay triangulation and the final "
      "intrinsic triangulation, with the exact (projective) map to the plane.")
      .readonly("vertices", &CommonRefinement::positions,
                "#R by 3 positions on the input surface: the input's vertices first, then the "
                "crossing points")
      .readonly("triangles", &CommonRefinement::triangles, "#T by 3")
      .readonly("input_face", &CommonRefinement::input_face, "#T: input face holding each")
      .readonly("delaunay_face", &CommonRefinement::delaunay_face,
                "#T: face of delaunay_topology holding each")
      .readonly("intrinsic_face", &CommonRefinement::intrinsic_face,
                "#T: face of the final triangulation (flow.topology) holding each")
      .readonly("input_vertex", &CommonRefinement::input_vertex,
                "#V: refinement vertex of each input vertex")
      .computed(
          "interpolation_triplets",
          [](const CommonRefinement& r) {
            std::vector<long> rows, cols;
            std::vector<double> values;
            for (int i = 0; i < r.interpolation.outerSize(); ++i) {
              for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(r.interpolation,
                                                                                  i);
                   it; ++it) {
                rows.push_back(it.row());
                cols.push_back(it.col());
                values.push_back(it.value());
              }
            }
            return py::make_tuple(py::array(py::cast(rows)), py::array(py::cast(cols)),
                                  py::array(py::cast(values)));
          },
          "(rows, cols, values) of the #R by #V interpolation matrix: barycentric weights of "
          "each refinement vertex over the input's vertices")
      .readonly("uv", &CommonRefinement::uv,
                "#UV by 2 linear texture coordinates in ParamResult.uv's unit square (its rows "
                "first)")
      .readonly("uv_triangles", &CommonRefinement::uv_triangles, "#T by 3 indices into uv")
      .readonly("projective_uv", &CommonRefinement::projective_uv,
                "3#T by 3: corner k of triangle t at row 3 t + k as (w u, w v, w); linear "
                "interpolation divided by w is the exact map")
      .readonly("delaunay_barycentric", &CommonRefinement::delaunay_barycentric,
                "3#T by 3: each corner in its Delaunay face")
      .readonly("intrinsic_barycentric", &CommonRefinement::intrinsic_barycentric,
                "3#T by 3: each corner in its final face")
      .readonly("delaunay_topology", &CommonRefinement::delaunay_topology,
                "Topology of the intrinsic Delaunay triangulation of the input")
      .readonly("delaunay_lengths", &CommonRefinement::delaunay_lengths, "its edge lengths")
      .readonly("isometric_flips", &CommonRefinement::isometric_flips, "")
      .readonly("ptolemy_flips", &CommonRefinement::ptolemy_flips, "")
      .readonly("input_delaunay_points", &CommonRefinement::input_delaunay_points, "")
      .readonly("delaunay_intrinsic_points", &CommonRefinement::delaunay_intrinsic_points, "")
      .readonly("interior_points", &CommonRefinement::interior_points, "")
      .readonly("max_intrinsic_length_error", &CommonRefinement::max_intrinsic_length_error,
                "relative, over final edges: uv length along the edge vs final length")
      .readonly("max_corner_mismatch", &CommonRefinement::max_corner_mismatch, "")
      .readonly("max_metric_mismatch", &CommonRefinement::max_metric_mismatch, "")
      .readonly("max_development_error", &CommonRefinement::max_development_error, "")
      .readonly("degenerate_triangles", &CommonRefinement::degenerate_triangles, "")
      .readonly("inverted_triangles", &CommonRefinement::inverted_triangles, "")
      .readonly("order_repairs", &CommonRefinement::order_repairs, "")
      .readonly("seconds", &CommonRefinement::seconds, "")
      .repr();

  // What parameterize returns first (it refuses several components), then one component's own
  // result (components[c].param).
  m.def(
      "common_refinement",
      py::overload_cast<const MeshParamResult&, const CommonRefinementOptions&>(&common_refinement),
      py::arg("param"), py::arg("options") = CommonRefinementOptions{},
      "The common refinement of a converged vertex-scaling ParamResult with the exact map. "
      "Raises InvalidInput for other schemes, an unconverged result or several components.");
  m.def("common_refinement",
        py::overload_cast<const Parameterization&, const CommonRefinementOptions&>(
            &common_refinement),
        py::arg("param"), py::arg("options") = CommonRefinementOptions{});
}

}  // namespace ricci::python
