/// \file
/// Bindings of shape matching (ricci/match/match.hpp): the correspondence as numpy arrays, and
/// the morph frames.
#include "bindings.hpp"
#include "ricci/match/match.hpp"
#include "ricci/mesh/validate.hpp"

namespace ricci::python {

void bind_match(py::module_& m) {
  m.def(
      "match_surfaces",
      [](const Mesh& a, const Mesh& b, const std::vector<std::pair<int, int>>& landmarks,
         bool reverse, int max_samples) {
        validate_mesh(a, "match: A");
        validate_mesh(b, "match: B");
        MatchOptions options;
        options.landmarks = landmarks;
        options.reverse = reverse;
        options.max_samples = max_samples;
        MatchResult r;
        {
          py::gil_scoped_release release;
          r = match_surfaces(a, b, options);
        }
        py::dict d;
        d["domain"] = enum_name(r.domain);
        d["converged"] = r.converged;
        d["exact"] = r.exact;
        d["message"] = r.message;
        d["faces"] = r.forward.face;
        d["barycentric"] = r.forward.weights;
        d["positions"] = mapped_positions(b, r.forward);
        d["outside"] = r.forward.outside;
        if (reverse) {
          d["reverse_faces"] = r.backward.face;
          d["reverse_barycentric"] = r.backward.weights;
          d["reverse_positions"] = mapped_positions(a, r.backward);
        }
        d["method"] = r.alignment.method;
        d["factor_mismatch"] = r.alignment.factor_mismatch;
        std::vector<double> distances;
        for (const LandmarkResidual& l : r.landmarks) distances.push_back(l.distance);
        d["landmark_distances"] = distances;
        d["landmark_rms"] = r.landmark_rms;
        d["landmark_max"] = r.landmark_max;
        d["modulus_a"] = r.modulus_a;
        d["modulus_b"] = r.modulus_b;
        d["modulus_distance"] = r.alignment.modulus_distance;
        d["affine_map"] = r.alignment.torus_linear;
        d["affine_distortion"] = r.alignment.torus_distortion;
        d["angle_distortion_mean"] = r.distortion.angle_distortion_mean;
        d["angle_distortion_max"] = r.distortion.angle_distortion_max;
        d["log_area_stddev"] = r.distortion.log_area_stddev;
        d["flipped_faces"] = r.distortion.flipped_faces;
        d["seconds"] = r.seconds;
        return d;
      },
      py::arg("a"), py::arg("b"), py::arg("landmarks") = std::vector<std::pair<int, int>>{},
      py::arg("reverse") = false, py::arg("max_samples") = 4000,
      "Correspondence of two surfaces through their canonical domains, as a dict of arrays. "
      "Raises InvalidInput, TopologyError.");
  m.def(
      "morph_frames",
      [](const Mesh& a, const Positions& target, int frames, bool rigid) {
        const std::vector<Positions> result = morph_frames(a, target, frames, rigid);
        py::array_t<double> out({static_cast<py::ssize_t>(result.size()),
                                 static_cast<py::ssize_t>(a.positions.rows()), py::ssize_t{3}});
        auto view = out.mutable_unchecked<3>();
        for (std::size_t k = 0; k < result.size(); ++k) {
          for (Eigen::Index v = 0; v < result[k].rows(); ++v) {
            for (int c = 0; c < 3; ++c) view(static_cast<py::ssize_t>(k), v, c) = result[k](v, c);
          }
        }
        return out;
      },
      py::arg("a"), py::arg("target"), py::arg("frames"), py::arg("rigid") = true,
      "Frames (frames, #V, 3) from A's positions to the target's. Raises InvalidInput.");
}

}  // namespace ricci::python
