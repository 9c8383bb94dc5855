/// \file
/// Bindings of the spherical conformal map (ricci/sphere/sphere.hpp).

#include "bindings.hpp"
#include "ricci/mesh/validate.hpp"
#include "ricci/sphere/sphere.hpp"

namespace ricci::python {

void bind_sphere(py::module_& m) {
  StructBinding<SphereOptions>(m, "SphereOptions", "Options of sphere_map.")
      .field("pole", &SphereOptions::pole, "vertex sent to the north pole first; -1 picks one")
      .field("structure", &SphereOptions::structure, "StructureOptions: the disk's discrete metric")
      .field("flow", &SphereOptions::flow, "FlowOptions (tolerance 1e-12 by default)")
      .field("centre_tolerance", &SphereOptions::centre_tolerance,
             "stop the Moebius normalisation when |centre of mass| <= this")
      .field("max_centre_iterations", &SphereOptions::max_centre_iterations,
             "most Newton steps of the normalisation")
      .field("untangle", &SphereOptions::untangle,
             "move the vertices of faces the map inverts into their stars' cones, then centre "
             "again")
      .keyword_constructor()
      .repr();

  StructBinding<SphereResult>(m, "SphereResult", "What sphere_map returns.")
      .readonly("converged", &SphereResult::converged,
                "the flow converged and the centre of mass reached its tolerance")
      .readonly("valid", &SphereResult::valid,
                "converged, no inverted face and every figure finite: the map to use")
      .computed(
          "message", [](const SphereResult& r) { return message_with_fixes(r.message, r.fixes); },
          "why not converged or not valid, when not (with the keywords that may help)")
      .computed(
          "fixes", [](const SphereResult& r) { return fix_pairs(r.fixes); },
          "(keyword, value) pairs that may help, best first")
      .readonly("positions", &SphereResult::positions, "#V by 3 positions on the unit sphere")
      .readonly("pole", &SphereResult::pole, "the vertex removed for the flow")
      .readonly("poles_tried", &SphereResult::poles_tried,
                "2 when the first pole's plane needed more than quad precision")
      .readonly("flow", &SphereResult::flow, "MeshFlowResult of the disk (disk vertex indices)")
      .readonly("disk_vertices", &SphereResult::disk_vertices,
                "per disk vertex: its vertex in the mesh")
      .readonly("reversed_disk_faces", &SphereResult::reversed_disk_faces,
                "disk faces reversed in the flat metric")
      .readonly("plane", &SphereResult::plane,
                "#V by 2 normalised layout of the disk (the pole's row NaN)")
      .readonly("layout_length_error", &SphereResult::layout_length_error, "")
      .readonly("boundary_circle_deviation", &SphereResult::boundary_circle_deviation,
                "max | |p| - 1 | over the disk's boundary in the normalised plane")
      .readonly("inverted_pole_faces", &SphereResult::inverted_pole_faces,
                "faces around the pole inverted by the projection (0 expected)")
      .readonly("precision_bits", &SphereResult::precision_bits,
                "significand bits of the layout, projection and normalisation: 53, 64 or 113")
      .readonly("min_plane_altitude", &SphereResult::min_plane_altitude,
                "smallest face altitude in the normalised plane")
      .readonly("min_sphere_altitude", &SphereResult::min_sphere_altitude,
                "smallest face altitude on the sphere, before rounding to double")
      .readonly("unresolved_faces", &SphereResult::unresolved_faces,
                "faces of altitude below 2^-46 on the sphere")
      .readonly("centre_iterations", &SphereResult::centre_iterations, "Newton steps")
      .readonly("initial_centre", &SphereResult::initial_centre,
                "|centre of mass| after the projection")
      .readonly("centre_of_mass", &SphereResult::centre_of_mass, "|centre of mass| at the end")
      .readonly("max_boost_norm", &SphereResult::max_boost_norm, "largest |a| of one step")
      .readonly("untangled_vertices", &SphereResult::untangled_vertices, "vertex moves made")
      .readonly("max_untangle_move", &SphereResult::max_untangle_move,
                "largest move, a chord of the unit sphere")
      .readonly("max_untangle_relative_move", &SphereResult::max_untangle_relative_move,
                "largest move over the vertex's shortest edge")
      .readonly("max_radius_deviation", &SphereResult::max_radius_deviation, "max | |P_i| - 1 |")
      .readonly("inverted_faces", &SphereResult::inverted_faces,
                "faces with det(P_i, P_j, P_k) <= 0 in the double positions")
      .readonly("inverted_by_rounding", &SphereResult::inverted_by_rounding,
                "of those, the faces kept by the map but inverted by rounding to double")
      .readonly("spherical_area", &SphereResult::spherical_area,
                "sum of signed spherical triangle areas (4 pi for a cover)")
      .readonly("angle_distortion_mean", &SphereResult::angle_distortion_mean,
                "sigma_max / sigma_min, 3D-area-weighted mean")
      .readonly("angle_distortion_max", &SphereResult::angle_distortion_max, "")
      .readonly("angle_distortion_p95", &SphereResult::angle_distortion_p95,
                "95th percentile over faces")
      .readonly("angle_error_mean", &SphereResult::angle_error_mean,
                "|chordal - 3D corner angle|, radians, mean over corners")
      .readonly("angle_error_max", &SphereResult::angle_error_max, "")
      .readonly("log_area_min", &SphereResult::log_area_min,
                "ln((spherical area / 4 pi) / (3D area share))")
      .readonly("log_area_max", &SphereResult::log_area_max, "")
      .readonly("log_area_mean", &SphereResult::log_area_mean, "3D-area-weighted")
      .readonly("log_area_stddev", &SphereResult::log_area_stddev, "3D-area-weighted")
      .readonly("flow_seconds", &SphereResult::flow_seconds, "")
      .readonly("layout_seconds", &SphereResult::layout_seconds, "")
      .readonly("normalisation_seconds", &SphereResult::normalisation_seconds, "")
      .readonly("seconds", &SphereResult::seconds, "")
      .repr();

  m.def("choose_pole_vertex", py::overload_cast<const Mesh&>(&choose_pole_vertex), py::arg("mesh"),
        "The default pole: the flattest vertex of valence >= 5.");
  m.def(
      "sphere_map",
      [](const Mesh& mesh, SphereOptions options) {
        validate_mesh(mesh, "sphere_map");
        return run_without_gil<SphereResult>(options.flow,
                                             [&] { return sphere_map(mesh, options); });
      },
      py::arg("mesh"), py::arg("options") = SphereOptions{},
      "Spherical conformal map of a closed genus-0 mesh. Raises InvalidInput, TopologyError.");
}

}  // namespace ricci::python
