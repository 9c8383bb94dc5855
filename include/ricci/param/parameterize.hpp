#pragma once
/// \file
/// The global conformal parameterization pipeline (tutorial sections 5 and 6): singularity
/// selection, local connectivity modification, Ricci flow to a flat metric with cones, cut graph,
/// planar layout, affine atlas and distortion figures. Mesh in, texture coordinates out.

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/flow/mesh_flow.hpp"
#include "ricci/mesh/polygons.hpp"
#include "ricci/param/atlas/atlas.hpp"
#include "ricci/param/atlas/chart_packing.hpp"
#include "ricci/param/cones/cones.hpp"
#include "ricci/param/cones/free_seams.hpp"
#include "ricci/param/cut/cut_graph.hpp"
#include "ricci/param/distortion.hpp"
#include "ricci/param/layout/layout.hpp"
#include "ricci/param/layout/polish.hpp"
#include "ricci/param/layout/untangle.hpp"

namespace ricci {

/// Where the cones come from.
enum class ConeMode {
  /// Cones only where the topology needs them: none on a torus or a surface with boundary (its
  /// flat metric exists without), automatic (Auto) on closed surfaces of genus 0 or >= 2.
  Needed,
  None,     ///< no cones: genus 1 closed, or any surface with boundary (free or disk boundary)
  User,     ///< ParamOptions::cones as given
  Auto,     ///< select_cones (a count, or until the log scale bound holds), also on surfaces
            ///< that need none
  OneCone,  ///< all curvature 2 pi chi at one vertex (genus >= 2), chosen by select_cones
};

template <>
struct EnumNames<ConeMode> {
  static constexpr const char* noun = "cone mode";
  static constexpr std::array<EnumName<ConeMode>, 5> names{{
      {ConeMode::Needed, "needed"},
      {ConeMode::None, "none"},
      {ConeMode::User, "user"},
      {ConeMode::Auto, "auto"},
      {ConeMode::OneCone, "one"},
  }};
};

/// "needed", "none", "user", "auto", "one". \throw InvalidInput otherwise
ConeMode parse_cone_mode(const std::string& name);
const char* cone_mode_name(ConeMode mode);

/// How the two copies of a seam (a cut edge) relate in the layout.
enum class SeamMode {
  /// The flat metric with cones: all curvature at the cones, every vertex off them flat, each
  /// seam's two copies related by a rigid motion (a rotation by the curvature the cut encloses
  /// and a translation). What a seamless or periodic texture needs; at low cone counts on genus
  /// >= 1 it distorts area strongly (the curvature of the handles has nowhere else to go).
  Rigid,
  /// Seams that may bend: the cones and the cut as chosen, then the cut's vertices (and a free
  /// boundary) carry the curvature that distorts least (free_seams.hpp) while both copies of
  /// every seam edge keep one length (texel density continuous across every seam; the rotation
  /// across it is free). What BFF writes on genus >= 1.
  Free,
};

template <>
struct EnumNames<SeamMode> {
  static constexpr const char* noun = "seam mode";
  static constexpr std::array<EnumName<SeamMode>, 2> names{{
      {SeamMode::Rigid, "rigid"},
      {SeamMode::Free, "free"},
  }};
};

/// "rigid", "free". \throw InvalidInput otherwise
SeamMode parse_seam_mode(const std::string& name);
const char* seam_mode_name(SeamMode mode);

/// What parameterize does about a component whose layout fails its own checks: faces drawn
/// flipped on the input's own faces, a layout that does not close up (a flat metric whose log
/// scale spans more than double precision can lay out), a flow that does not converge or that
/// refuses the component's cones.
struct FoldFreeOptions {
  /// Untangle flipped faces (untangle.hpp): the vertices around them move, a seam vertex with
  /// all its copies, so that cones, congruent seams and the boundary stay exact.
  bool untangle = true;
  /// Where the exact map still fails: the component cut along a cut graph into a disk flattened
  /// with a free boundary (u = 0 on the cut, so both sides of every seam keep their 3D length),
  /// faces that still fold laid out in their own 3D shape, overlapping layouts split into
  /// pieces: ComponentMethod::Charts, never a flipped face. Off: the failing layout is returned
  /// as it is (converged false when it does not close up or folds).
  bool charts = true;
  /// A layout whose largest relative edge length error exceeds this does not close up.
  double max_length_error = 1e-6;
};

/// Options of parameterize.
struct ParamOptions {
  ConeMode cone_mode = ConeMode::Needed;
  std::vector<Cone> cones;          ///< ConeMode::User: vertices (input indices) and curvatures
  ConeSelectionOptions auto_cones;  ///< ConeMode::Auto: count or log-scale bound
  bool quantize = false;            ///< round cone curvatures to multiples of pi/2
  /// Rigid seams (the flat metric with cones) or seams that may bend (SeamMode::Free).
  SeamMode seams = SeamMode::Rigid;
  FreeSeamOptions free_seams;  ///< SeamMode::Free: how the seams' curvature is chosen
  /// A mesh of several components: how their charts are packed into the unit square.
  ChartPackingOptions packing;
  BoundaryMode boundary = BoundaryMode::Free;  ///< free or disk boundary
  StructureOptions structure;                  ///< discrete metric scheme
  /// Newton to 1e-12, see layout_flow_options.
  FlowOptions flow = layout_flow_options();
  /// Without edge flips (the circle packings): split edges around cones whose valence breaks the
  /// single-vertex bound (tutorial 5.3), and subdivide once when the flow still degenerates.
  /// With flips (vertex scaling, the default) every admissible target is reached on the input's
  /// own triangulation, which is never modified.
  bool modify_connectivity = true;
  /// After the layout, move the vertices on no seam and no boundary to lower the faces' mean
  /// angle distortion (polish_angles); seams, cones and boundary stay exact. Off: the layout is
  /// the discrete conformal map itself (every edge as long as the flat metric says), which
  /// common_refinement needs.
  PolishOptions polish;
  FoldFreeOptions fold_free;  ///< untangling, and the charts where the exact map fails
  /// A polygon mesh (ReadResult::polygons of read_mesh): the faces the mesh's triangles make up.
  /// Their diagonals are never cut (CutGraphOptions::uncut_edges), a layout split into pieces
  /// keeps each polygon in one, and the result's polygons (ParamResult::polygons) give the faces
  /// to write. Empty: every triangle is a face. Ignored when edge splits change the faces
  /// (valence raising and subdivision, circle packings only): on a mesh of several components,
  /// edge splits in any of them leave the whole mesh's polygons empty (its triangles written).
  Polygons polygons;
};

/// Wall time of each stage of parameterize, seconds.
struct ParamTimings {
  double cones = 0;        ///< topology checks and cone selection
  double flow = 0;         ///< connectivity modification and the Ricci flow
  double cut = 0;          ///< cut graph and slicing
  double development = 0;  ///< the input's faces developed in the flow's metric
  double layout = 0;       ///< planar layout (with its least-squares refinement)
  double polish = 0;       ///< angle polish of the layout's interior
  double untangle = 0;     ///< untangling of flipped faces
  double charts = 0;       ///< the charts route (components whose exact map failed its checks)
  double atlas = 0;        ///< affine atlas
  double distortion = 0;   ///< distortion figures
};

/// How a component was laid out: the route its layout took (MeshParamResult::routes, and
/// ComponentParam::method where the component went through the atlas's path).
enum class ComponentMethod {
  /// The pipeline's exact map: cones, flow, cut, layout (every vertex at its image under the flat
  /// metric with cones, polished), fold-free as it came.
  Flow,
  /// The pipeline's exact map with the faces it drew flipped untangled (untangle.hpp): cones,
  /// congruent seams and the boundary as the flat metric has them.
  Untangled,
  /// The exact map failed its checks (FoldFreeOptions): the component cut along a cut graph into
  /// a disk flattened with a free boundary (both sides of every seam at their 3D length), faces
  /// that still folded laid out in their own shape, overlapping layouts split: several charts,
  /// no cone singularities (the seams carry the curvature), never a flipped face.
  Charts,
  /// Its own faces laid out in their 3D shapes as one chart (an unfolding: each face developed
  /// across an edge of one already placed, none overlapping another): components of one or two
  /// faces, and, when this works, components whose pipeline failed or whose flow layout distorts
  /// angles by more than a factor 10 somewhere (tiny closed parts with the few cones their
  /// topology needs). No distortion at all; its cones are its curved interior vertices (3D angle
  /// sum not 2 pi), and its cut runs between faces that were not laid out side by side.
  Unfolded,
  /// The pipeline failed, the charts were not allowed or failed too, and the unfolding needed
  /// several patches not to overlap: each patch its own chart, as above. The component counts
  /// as failed.
  Patches,
};

template <>
struct EnumNames<ComponentMethod> {
  static constexpr const char* noun = "component method";
  static constexpr std::array<EnumName<ComponentMethod>, 5> names{{
      {ComponentMethod::Flow, "flow"},
      {ComponentMethod::Untangled, "untangled"},
      {ComponentMethod::Charts, "charts"},
      {ComponentMethod::Unfolded, "unfolded"},
      {ComponentMethod::Patches, "patches"},
  }};
};

/// A parameterization: the mesh, its cut, its layout and texture coordinates, and what the flow,
/// the polish and the untangling did to get there. Each field means the same for one component
/// (ParamResult, in the component's own indices) and for the whole mesh (MeshParamResult, in the
/// whole mesh's indices), so the writers, the pictures and the refinement read either.
struct Parameterization {
  /// The flow reached its tolerance (the charts and the unfolding: laid out without a flipped
  /// face).
  bool converged = false;
  std::string message;  ///< why not, when it did not
  /// The mesh parameterized: the input itself (same vertices, faces and order), except that the
  /// Thurston scheme's valence raising (modify_connectivity) appends the vertices its edge splits
  /// add. With edge flips the flat metric lives on the flow's intrinsic triangulation
  /// (flow.intrinsic), and the layout places the input's own faces in it.
  Mesh mesh;
  std::vector<int> vertex_origin;  ///< per output vertex: input vertex, or -1 when added
  std::vector<std::array<int, 2>> added_vertex_parents;  ///< per added vertex: the edge it splits
  int edge_splits = 0;  ///< connectivity modifications made (edges split)
  /// The flow degenerated around a strong cone even after raising its valence, so the whole mesh
  /// was subdivided once (every edge split at its midpoint) and the flow run again.
  bool subdivided = false;
  std::vector<Cone> cones;  ///< final cones (output vertex indices) and curvatures
  MeshFlowResult flow;      ///< the Ricci flow to the flat metric
  CutGraph cut;
  CutMesh cut_mesh;
  /// Raw layout (metric units). With ParamOptions::polish its interior vertices have moved
  /// (polish); its seams, cones and boundary, transitions and lattice are the flat metric's.
  Layout layout;
  /// The angle polish. Its uv holds the layout before the polish, the flat metric's own
  /// positions (layout.uv holds the polished ones; common_refinement reads these); empty when
  /// the polish did not run.
  PolishResult polish;
  /// The untangling of the faces the layout drew flipped (FoldFreeOptions::untangle): its uv is
  /// moved into the layout (empty here); flipped_before 0 when there was nothing to do.
  UntangleResult untangle;
  AffineAtlas atlas;
  /// Of the faces written: the triangles, or with polygons the fan of each polygon from its
  /// first corner (measure_polygon_distortion), as a reader of the file splits them.
  Distortion distortion;
  double seam_length = 0;  ///< 3D length of the cut edges
  /// The faces to write (textured_mesh), for ParamOptions::polygons: those polygons over mesh's
  /// triangles, each listed from a corner whose fan from there is drawn unflipped in the layout
  /// (start_fans_where_valid of ricci/param/layout/polygon_fans.hpp: the same face, a reader
  /// splitting it as a fan from its first corner gets a sound one), and distortion measures
  /// those fans. Every polygon has one uv per corner: no cut runs inside it. Empty without
  /// polygons, and when edge splits changed the faces (then the triangles are written).
  Polygons polygons;
  /// Texture coordinates in the unit square (aspect ratio kept): one per cut-mesh vertex;
  /// uv_triangles = cut_mesh.triangles indexes them per corner.
  Eigen::Matrix<double, Eigen::Dynamic, 2> uv;
  double uv_scale = 1;  ///< uv = (layout - offset) * uv_scale
  Eigen::Vector2d uv_offset = Eigen::Vector2d::Zero();
  double seconds = 0;
  ParamTimings timings;
};

/// Curvature on the seams (PipelineDiagnostics::seam_curvature), of the final metric.
struct SeamCurvature {
  int vertices = 0;               ///< vertices of the cut that are not cones (nor on the boundary)
  double total = 0;               ///< sum of |K| over them
  double max = 0;                 ///< largest |K| among them
  double free_seconds = 0;        ///< SeamMode::Free: time to choose it (free_seam_target)
  double linear_area_energy = 0;  ///< SeamMode::Free: E of the linearised choice
  /// SeamMode::Free: vertices whose chosen curvature was held at 1.75 pi (kMaxFreeCurvature)
  int capped_vertices = 0;
  /// SeamMode::Free: the map with rigid seams (seams that carry no curvature, which free seams
  /// allow) was made too, since the free seams' map was in doubt (kFreeSeamsCheckEnergy); it
  /// distorted less, and is the result. vertices, total and max are then the rigid map's;
  /// free_seconds, linear_area_energy and capped_vertices the free choice's.
  bool rigid_kept = false;
  /// SeamMode::Free, when the rigid map was made: the free seams' map's E (eq. 9), and the
  /// rigid one's; 0 when it was not made.
  double free_area_energy = 0;
  double rigid_area_energy = 0;
};

/// SeamMode::Free: a map whose area distortion E exceeds this, or exceeds twice the E its
/// linearised choice promised (and 0.05), is compared with the rigid map of the same cone
/// option (a count, the user's cones, automatic), and the rigid one is kept when both pass the
/// exact map's checks and it has the lower E with angle distortion at most 5 % higher
/// (SeamCurvature::rigid_kept). On the
/// reference meshes the free maps stay within 1.3 times their linearised E; where the choice
/// breaks down (needle faces: a CAD cylinder's promised 0.013 became 126) or the linearised E is
/// a poor guide (a cow's head with its free boundary: 17.8 against the rigid map's 3.4), the
/// rigid map is a valid map with free seams that carry nothing.
inline constexpr double kFreeSeamsCheckEnergy = 1.0;

/// Few automatic cones on a closed surface of chi < 0, refined on the flow
/// (PipelineDiagnostics::cone_refinement): the two candidate sets measured by their flat
/// metrics' area distortion E, the better one's curvatures refined (refine_cone_curvatures).
struct ConeRefinementReport {
  bool ran = false;            ///< the count was too few for the selection's bounds
  bool level_cones = false;    ///< the level cones (select_level_cones) were kept
  double selected_energy = 0;  ///< E of the bounded selection's cones (inf: no flow)
  double level_energy = 0;     ///< E of the level cones (inf: no flow)
  double refined_energy = 0;   ///< E after refining the kept set
  int steps = 0, flows = 0;    ///< the refinement's quasi-Newton steps and flows
};

/// What the one-component pipeline measured on its way beyond the map itself: how its automatic
/// cones went, and how its development closed up, what its seams carry. A ParamResult's own; in a
/// MeshParamResult, per component in ComponentRoute::pipeline.
struct PipelineDiagnostics {
  ConeSelection cone_selection;  ///< ConeMode::Auto / OneCone: the greedy history (last round)
  /// Automatic cones with flips: max |u - mean u| of the flat metric's own log scale, away from
  /// the cones (log_scale_spread); 0 when not measured.
  double log_scale_spread = 0;
  /// Automatic cones: how many times they were chosen again, with more of them, because the
  /// flat metric's spread exceeded 1.25 max_log_scale (the linearised model underestimates
  /// strong cones); each round's flow is counted in timings.flow.
  int cone_rounds = 0;
  /// With flips: how well the development of the input faces in the intrinsic metric closes up
  /// (largest relative difference of an input edge's length seen from its two faces).
  double development_length_mismatch = 0;
  /// The curvature the flat metric leaves on the seams: at the cut's vertices that are not
  /// cones. About 0 (the flow's tolerance) with rigid seams; with free seams what they carry.
  SeamCurvature seam_curvature;
  ConeRefinementReport cone_refinement;
  /// Set when the cones asked for (a count, or the user's) are too few for an exact map of this
  /// genus to be good (rigid seams on genus >= 1, area distortion E above kTooFewConesEnergy, or
  /// faces that fold around strong cones, whatever route then stood in for the map):
  /// says so and names the remedies (more cones, SeamMode::Free). Empty otherwise.
  std::string too_few_cones;
  /// Free seams: set when they gave way to the rigid map (SeamCurvature::rigid_kept), with both
  /// maps' E, or when their map stayed though its E exceeds kFreeSeamsCheckEnergy. Empty
  /// otherwise.
  std::string free_seams_note;
};

/// Area distortion E (eq. 9) above which a rigid map of genus >= 1 with the cones asked for is
/// reported as having too few of them (PipelineDiagnostics::too_few_cones): every face's area
/// off by about its own size on average.
inline constexpr double kTooFewConesEnergy = 1.0;

/// One component parameterized by one route: the pipeline's exact map (cones, flow, cut, layout,
/// atlas, distortion), or a route that stood in for it (charts, unfolding; their diagnostics at
/// their defaults). Every index is the component's own. What parameterize returns for the whole
/// mesh is a MeshParamResult.
struct ParamResult : Parameterization, PipelineDiagnostics {};

/// The route one component's layout took, and what it cost (MeshParamResult::routes).
struct ComponentRoute {
  ComponentMethod method = ComponentMethod::Flow;
  int charts = 1;          ///< charts of its layout in the atlas
  double seam_length = 0;  ///< 3D length of its seams (cut edges, edges between charts)
  /// Faces the exact map drew flipped, before untangling (0 when it did not get that far).
  int flipped_before = 0;
  int flipped = 0;  ///< faces flipped in its final layout
  /// Why the exact map gave way (its refusal, non-convergence, length error or folds left
  /// after untangling); empty for Flow and Untangled.
  std::string why;
  /// What its exact map's pipeline measured (automatic cones, development) when that map served
  /// (Flow, Untangled; Patches: the failed one's); defaults for Charts and Unfolded, which stand
  /// in for the pipeline.
  PipelineDiagnostics pipeline;
};

/// "flow", "untangled", "charts", "unfolded" or "patches" (its EnumNames row), as reports print
/// it.
const char* component_method_name(ComponentMethod method);

/// One component on its way into the atlas (MeshParamResult::components).
struct ComponentParam {
  std::vector<int> vertices;  ///< input vertices of the component, ascending
  std::vector<int> faces;     ///< input faces of the component, ascending
  int euler_characteristic = 0, genus = 0, boundary_loops = 0;
  ComponentMethod method = ComponentMethod::Flow;
  /// Laid out without a flipped face by one of the routes (false for Patches: the failed
  /// pipeline's component laid out as patches of its own shape).
  bool parameterized = false;
  /// Why the pipeline failed (its message, or the exception it threw), also when the unfolding
  /// then served, or why its layout gave way to the unfolding; empty when the flow served.
  std::string message;
  std::vector<Cone> cones;  ///< its cones, in vertices of MeshParamResult::mesh
  Distortion distortion;    ///< of its own part of the atlas
  /// Pairs of its faces that overlap in its own layout (find_uv_overlaps): a conformal layout
  /// without flipped faces can still wind over itself (the arms of triple_vierbein, a surface
  /// of many holes cut into one disk); 0 for Unfolded and Patches by construction. Such a layout
  /// is cut into pieces that do not overlap (grown face by face across its edges), each its own
  /// chart, so that the atlas never has two faces on the same texels.
  int overlapping_face_pairs = 0;
  double seam_length = 0;  ///< 3D length of its cut edges
  /// Its layout was multiplied by this before packing, so that its layout area equals its 3D
  /// area: every component then has the same mean texel density.
  double area_scale = 1;
  /// Its charts in MeshParamResult::packing.charts: one, unless Patches or its layout overlapped
  /// itself (overlapping_face_pairs).
  std::vector<int> charts;
  std::vector<int> vertex_map;  ///< #V of param.mesh: the vertex of MeshParamResult::mesh
  std::vector<int> face_map;    ///< #F of param.mesh: the face of MeshParamResult::mesh
  /// Its vertices of MeshParamResult::cut_mesh start here: vertex i of its cut mesh (param.cut_mesh
  /// when it has one chart) is cut_vertex_offset + i.
  int cut_vertex_offset = 0;
  double seconds = 0;
  /// The component alone, in its own indices (param.mesh is the component, plus the vertices
  /// edge splits added): the pipeline's result (Flow; Patches: the failed one, its mesh the
  /// component's) or the unfolding's (Unfolded: converged, no flow; its cut has no segments).
  ParamResult param;
};

/// What parameterize returns: the whole mesh's parameterization (its Parameterization fields of
/// the whole mesh, in the whole mesh's indices), each component's route, and the components the
/// atlas was gathered from.
/// - A mesh of one component whose exact map passed its checks (or had nothing to give way to):
///   that map as the pipeline made it; `components` is empty, routes[0].pipeline holds its
///   diagnostics.
/// - Otherwise (several components, or one whose exact map gave way to another route) the atlas
///   gathered from `components`: mesh (the input's vertices, then the vertices each component's
///   edge splits added, component after component; the input's faces in their order, a
///   component whose faces edge splits changed giving all of its faces at the place of its
///   first), vertex_origin, added_vertex_parents, cones, cut (whole-mesh edges; segments and
///   nodes of the components in one chart), cut_mesh, layout (uv: the packed atlas in layout
///   units, uv = layout.uv * uv_scale up to rounding; transitions and segment transitions moved
///   with the charts, of components in one chart; no lattice), atlas (moved likewise),
///   distortion and seam_length of the whole atlas; flow gathers the Flow and Untangled
///   components' flows (converged, max_error, flips, components with whole-mesh vertices, u,
///   curvature, target_curvature; their topology, lengths, structure and flip list stay in
///   components[c].param.flow); untangle sums the components' (Patches aside); polish and
///   timings gather the Flow and Untangled components' (counts and seconds summed, the polish's
///   sweeps their maximum and its face means weighted by face counts, its uv empty; the charts'
///   time of every component). converged: every component parameterized; message: which ones
///   were not.
struct MeshParamResult : Parameterization {
  /// One entry per connected component of the input, in the order of Topology::components, when
  /// the atlas was gathered from them (see above); empty when the whole mesh is one component
  /// its exact map laid out.
  std::vector<ComponentParam> components;
  /// How the components' charts were packed (its uv moved into `uv`, so empty here); empty with
  /// `components`.
  ChartPacking packing;
  /// Per component, in the order of Topology::components (one entry for a mesh of one
  /// component): the route its layout took. A component whose exact map fails its own checks
  /// (FoldFreeOptions) goes through the components' path (components[c], packing) even when it
  /// is the only one.
  std::vector<ComponentRoute> routes;
};

/// Runs the pipeline: cones, connectivity modification, flow, cut, layout, atlas, distortion,
/// uv in the unit square (aspect ratio kept).
///
/// Several components: each is parameterized on its own with the same options (user cones go to
/// the components of their vertices; automatic cones are chosen per component). A component of
/// one or two faces is unfolded; one whose pipeline fails (not converged, or InvalidInput,
/// TopologyError, SolverError) is unfolded, in several patches if one would overlap itself, and
/// the others go on. Each component's layout is scaled to its 3D area and the charts are
/// packed into the unit square (pack_charts with options.packing); MeshParamResult says what the
/// gathered result holds. A flow cancelled by its progress callback stops everything: the result
/// then has no uv, converged false and the components done so far (one component: its result as
/// the cancelled flow left it, no other route tried).
/// \throw InvalidInput (bad cones; one component: also an inadmissible target or cone mode),
///        TopologyError
MeshParamResult parameterize(const Mesh& mesh, const ParamOptions& options = {});

}  // namespace ricci
