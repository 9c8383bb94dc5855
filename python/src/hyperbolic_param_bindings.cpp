/// \file
/// Bindings of the hyperbolic parameterization (ricci/hyperbolic/hyperbolic_param.hpp): the layout
/// in the Poincare disk, the segment maps and the Fuchsian group. A Moebius map reaches Python as
/// its 2 by 2 complex matrix [[a, b], [conj b, conj a]] (numpy complex128, determinant 1 up to
/// rounding), acting by z -> (a z + b) / (conj(b) z + conj(a)); composition is the matrix product.

#include <complex>
#include <vector>

#include "bindings.hpp"
#include "ricci/hyperbolic/hyperbolic_param.hpp"
#include "ricci/mesh/validate.hpp"

namespace ricci::python {
namespace {

/// The SU(1,1) matrix of a Moebius map.
Eigen::Matrix2cd mobius_matrix(const Mobius& m) {
  Eigen::Matrix2cd out;
  out << m.a, m.b, std::conj(m.b), std::conj(m.a);
  return out;
}

std::vector<Eigen::Matrix2cd> mobius_matrices(const std::vector<Mobius>& maps) {
  std::vector<Eigen::Matrix2cd> out;
  out.reserve(maps.size());
  for (const Mobius& m : maps) out.push_back(mobius_matrix(m));
  return out;
}

}  // namespace

void bind_hyperbolic_param(py::module_& m) {
  StructBinding<HyperbolicLayoutOptions>(m, "HyperbolicLayoutOptions",
                                         "Options of the layout in the Poincare disk.")
      .field("root_face", &HyperbolicLayoutOptions::root_face,
             "face placed first, its first corner at the centre; -1: the face farthest from the "
             "cut")
      .field("recentre", &HyperbolicLayoutOptions::recentre,
             "move the domain's area-weighted centre to the centre of the disk afterwards")
      .keyword_constructor()
      .repr();

  StructBinding<SegmentIsometry>(m, "SegmentIsometry", "The deck transformation of a cut segment.")
      .readonly("segment", &SegmentIsometry::segment, "")
      .readonly("edge", &SegmentIsometry::edge, "the segment's first edge")
      .computed(
          "map", [](const SegmentIsometry& s) { return mobius_matrix(s.map); },
          "2 by 2 complex matrix [[a, b], [conj b, conj a]] taking side B onto side A")
      .readonly("mismatch", &SegmentIsometry::mismatch,
                "hyperbolic distance between the mapped side-B and the side-A copies, relative "
                "to the edge length")
      .readonly("translation_length", &SegmentIsometry::translation_length,
                "how far the map moves the points of its axis")
      .repr();

  StructBinding<HyperbolicLayout>(m, "HyperbolicLayout",
                                  "Layout of a hyperbolic metric in the Poincare disk.")
      .readonly("uv", &HyperbolicLayout::uv, "#V_cut by 2 positions in the unit disk")
      .readonly("root_face", &HyperbolicLayout::root_face, "")
      .readonly("max_length_relative_error", &HyperbolicLayout::max_length_relative_error,
                "max over edges of |hyperbolic distance - length| / length")
      .readonly("num_flipped_faces", &HyperbolicLayout::num_flipped_faces, "0 expected")
      .readonly("max_radius", &HyperbolicLayout::max_radius, "largest |z| of a vertex")
      .readonly("segment_maps", &HyperbolicLayout::segment_maps, "SegmentIsometry per cut segment")
      .readonly("node_words", &HyperbolicLayout::node_words,
                "per cut-graph node: [(segment, +1 or -1), ...] crossed going around it (empty "
                "on a boundary); the product of the maps in this order is the identity")
      .repr();

  StructBinding<FuchsianGroup>(m, "FuchsianGroup",
                               "Canonical generators a_i, b_i of a closed surface's Fuchsian "
                               "group: a_1 b_1 a_1^-1 b_1^-1 ... a_g b_g a_g^-1 b_g^-1 = +-I.")
      .readonly("genus", &FuchsianGroup::genus, "")
      .computed(
          "a", [](const FuchsianGroup& g) { return mobius_matrices(g.a); },
          "g 2 by 2 complex matrices [[a, b], [conj b, conj a]], determinant 1")
      .computed(
          "b", [](const FuchsianGroup& g) { return mobius_matrices(g.b); }, "as a")
      .readonly("a_words", &FuchsianGroup::a_words,
                "a_i as words [(segment, +1 or -1), ...] in the segment maps, left to right")
      .readonly("b_words", &FuchsianGroup::b_words, "")
      .readonly("relator", &FuchsianGroup::relator, "the single relator after Tietze reduction")
      .readonly("generator_segments", &FuchsianGroup::generator_segments, "")
      .readonly("tree_segments", &FuchsianGroup::tree_segments, "")
      .readonly("root_node", &FuchsianGroup::root_node, "")
      .readonly("relation_residual", &FuchsianGroup::relation_residual,
                "max-norm of the product of commutators -+ I")
      .readonly("relation_scale", &FuchsianGroup::relation_scale,
                "product of the operator norms of its 4 g factors")
      .readonly("node_residual", &FuchsianGroup::node_residual,
                "max over the node words of the distance of their product to +-I")
      .readonly("largest_generator_norm", &FuchsianGroup::largest_generator_norm, "")
      .repr();

  StructBinding<HyperbolicParamOptions>(m, "HyperbolicParamOptions",
                                        "Options of parameterize_hyperbolic.")
      .field("structure", &HyperbolicParamOptions::structure,
             "StructureOptions (the geometry is set to hyperbolic)")
      .field("flow", &HyperbolicParamOptions::flow, "FlowOptions (tolerance 1e-12 by default)")
      .field("layout", &HyperbolicParamOptions::layout, "HyperbolicLayoutOptions")
      .field("cut_candidates", &HyperbolicParamOptions::cut_candidates,
             "closed surfaces: most cuts (tree-cotree roots) tried for the best-conditioned group")
      .field("good_relation_residual", &HyperbolicParamOptions::good_relation_residual,
             "stop trying cuts once the relation residual is this small")
      .field("polygons", &HyperbolicParamOptions::polygons,
             "Polygons (read_mesh's info.polygons): faces whose diagonals are never cut")
      .keyword_constructor()
      .repr();

  StructBinding<HyperbolicParamResult>(m, "HyperbolicParamResult",
                                       "What parameterize_hyperbolic returns.")
      .readonly("converged", &HyperbolicParamResult::converged, "the flow reached its tolerance")
      .readonly("message", &HyperbolicParamResult::message, "why not, when it did not")
      .readonly("uv", &HyperbolicParamResult::uv,
                "#V_cut by 2 texture coordinates in the Poincare disk (|uv| < 1)")
      .computed(
          "uv_triangles", [](const HyperbolicParamResult& r) { return r.cut_mesh.triangles; },
          "#F by 3 indices into uv per corner of the input's faces (cut_mesh.triangles)")
      .computed(
          "segment_maps",
          [](const HyperbolicParamResult& r) {
            std::vector<Eigen::Matrix2cd> out;
            for (const SegmentIsometry& s : r.layout.segment_maps)
              out.push_back(mobius_matrix(s.map));
            return out;
          },
          "per cut segment: 2 by 2 complex matrix taking side B onto side A (layout.segment_maps)")
      .computed(
          "node_words", [](const HyperbolicParamResult& r) { return r.layout.node_words; },
          "layout.node_words")
      .readonly("has_group", &HyperbolicParamResult::has_group,
                "closed surface: the Fuchsian group was computed")
      .readonly("group_failure", &HyperbolicParamResult::group_failure,
                "closed surface whose group could not be computed: why (else empty)")
      .computed(
          "group",
          [](const HyperbolicParamResult& r) -> py::object {
            if (!r.has_group) return py::none();
            return py::cast(r.group);
          },
          "FuchsianGroup, or None on a surface with boundary")
      .readonly("distortion", &HyperbolicParamResult::distortion,
                "Distortion of the disk layout against the mesh")
      .readonly("polygons", &HyperbolicParamResult::polygons,
                "Polygons to write (options.polygons, each from a corner whose fan is sound)")
      .readonly("seam_length", &HyperbolicParamResult::seam_length, "3D length of the cut edges")
      .readonly("flow", &HyperbolicParamResult::flow, "MeshFlowResult")
      .readonly("cut", &HyperbolicParamResult::cut, "CutGraph")
      .readonly("cut_mesh", &HyperbolicParamResult::cut_mesh, "CutMesh")
      .readonly("layout", &HyperbolicParamResult::layout, "HyperbolicLayout")
      .readonly("seconds", &HyperbolicParamResult::seconds, "")
      .readonly("cut_candidates_tried", &HyperbolicParamResult::cut_candidates_tried,
                "cuts laid out before the kept one was chosen")
      .readonly("cut_root", &HyperbolicParamResult::cut_root,
                "root vertex of the kept cut (-1: cut_graph's default)")
      .readonly("development_length_mismatch", &HyperbolicParamResult::development_length_mismatch,
                "after flips: how well the input faces developed in the metric agree on their "
                "shared edges (relative)")
      .computed(
          "refined_error",
          [](const HyperbolicParamResult& r) { return r.refinement.max_error_after; },
          "max |K-bar - K| of the metric refined in long double (the layout's metric)")
      .repr();

  m.def(
      "parameterize_hyperbolic",
      [](const Mesh& mesh, HyperbolicParamOptions options) {
        validate_mesh(mesh, "parameterize_hyperbolic");
        return run_without_gil<HyperbolicParamResult>(
            options.flow, [&] { return parameterize_hyperbolic(mesh, options); });
      },
      py::arg("mesh"), py::arg("options") = HyperbolicParamOptions{},
      "Parameterization of a single-component mesh with chi < 0 in the Poincare disk (validated "
      "first). Raises InvalidInput (chi >= 0, several components), TopologyError.");
}

}  // namespace ricci::python
