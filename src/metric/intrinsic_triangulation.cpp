#include "ricci/metric/intrinsic_triangulation.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "ricci/errors.hpp"
#include "ricci/metric/angles.hpp"
#include "ricci/metric/delaunay_flips.hpp"

namespace ricci {
namespace {

using Complex = std::complex<double>;

/// The two halfedges of a flipped edge at the moment of its flip: h0 in face f0 opposite its
/// corner k0 (the new diagonal's corner a), h1 likewise (corner b).
struct FlipRecord {
  int h0, h1;
};

double cross(Complex a, Complex b) {
  return a.real() * b.imag() - a.imag() * b.real();
}

/// Replays the flips on `t` in place, recording their halfedges.
std::vector<FlipRecord> replay(Topology& t, const std::vector<int>& flipped_edges) {
  std::vector<FlipRecord> records;
  records.reserve(flipped_edges.size());
  for (std::size_t i = 0; i < flipped_edges.size(); ++i) {
    const int e = flipped_edges[i];
    if (e < 0 || e >= t.num_edges || !can_flip_edge(t, e)) {
      throw InvalidInput("replay_flips: flip " + std::to_string(i) + " names edge " +
                         std::to_string(e) + ", which " +
                         (e < 0 || e >= t.num_edges ? "does not exist"
                                                    : "cannot be flipped in the triangulation "
                                                      "the earlier flips leave"));
    }
    records.push_back({t.edge_halfedges(e, 0), t.edge_halfedges(e, 1)});
    flip_edge(t, e);
  }
  return records;
}

}  // namespace

Topology replay_flips(const Topology& input, const std::vector<int>& flipped_edges) {
  Topology t = input;
  replay(t, flipped_edges);
  return t;
}

FaceShapes face_shapes_from_lengths(const Topology& topology, const Eigen::VectorXd& lengths) {
  CornerAngles angles;
  const int bad = corner_angles(topology, lengths, angles);
  if (bad >= 0) {
    throw InvalidInput("face_shapes_from_lengths: face " + std::to_string(bad) +
                       " breaks a triangle inequality");
  }
  FaceShapes shapes(static_cast<std::size_t>(topology.num_faces));
  for (int f = 0; f < topology.num_faces; ++f) {
    shapes[f] = {Complex{0}, Complex{lengths[topology.face_edges(f, 2)]},
                 std::polar(lengths[topology.face_edges(f, 1)], angles(f, 0))};
  }
  return shapes;
}

Development develop_input_faces(const Topology& input, const std::vector<int>& flipped_edges,
                                const Eigen::VectorXd& final_lengths) {
  Topology t = input;
  const std::vector<FlipRecord> records = replay(t, flipped_edges);
  if (final_lengths.size() != t.num_edges) {
    throw InvalidInput("develop_input_faces: " + std::to_string(final_lengths.size()) +
                       " lengths for " + std::to_string(t.num_edges) + " edges");
  }
  Development d;
  d.shapes = face_shapes_from_lengths(t, final_lengths);
  FaceShapes& shapes = d.shapes;
  // Undo the flips, last first. Before the flip of record r, face f0 read (c, a, b) and f1
  // (d, b, a) from corners k0 and k1; flip_edge turned them into (a, d, c) and (b, c, d).
  for (auto r = records.rbegin(); r != records.rend(); ++r) {
    const int f0 = r->h0 / 3, k0 = r->h0 % 3, f1 = r->h1 / 3, k1 = r->h1 % 3;
    auto& p0 = shapes[f0];
    auto& p1 = shapes[f1];
    const Complex a = p0[k0], d0 = p0[(k0 + 1) % 3], c0 = p0[(k0 + 2) % 3];
    const Complex b1 = p1[k1], c1 = p1[(k1 + 1) % 3], d1 = p1[(k1 + 2) % 3];
    // The rigid motion taking f1's copy of the shared edge cd onto f0's: rotation from the two
    // directions, translation matching the midpoints (the copies agree up to rounding).
    Complex rotation = (d0 - c0) / (d1 - c1);
    rotation /= std::abs(rotation);
    const Complex b = 0.5 * (c0 + d0) + rotation * (b1 - 0.5 * (c1 + d1));
    p0 = {c0, a, b};
    std::rotate(p0.begin(), p0.begin() + (3 - k0) % 3, p0.end());
    p1 = {d0, b, a};
    std::rotate(p1.begin(), p1.begin() + (3 - k1) % 3, p1.end());
  }

  d.lengths.resize(input.num_edges);
  auto side = [&](int h) {
    const auto& p = shapes[h / 3];
    return std::abs(p[(h % 3 + 2) % 3] - p[(h % 3 + 1) % 3]);
  };
  for (int e = 0; e < input.num_edges; ++e) {
    const double la = side(input.edge_halfedges(e, 0));
    d.lengths[e] = la;
    if (input.edge_halfedges(e, 1) >= 0) {
      const double lb = side(input.edge_halfedges(e, 1));
      d.max_length_mismatch = std::max(d.max_length_mismatch, std::abs(la - lb) / std::max(la, lb));
    }
  }
  for (int f = 0; f < input.num_faces; ++f) {
    const auto& p = shapes[f];
    const double area = cross(p[1] - p[0], p[2] - p[0]);
    const double scale =
        std::max({std::norm(p[1] - p[0]), std::norm(p[2] - p[1]), std::norm(p[0] - p[2])});
    if (std::abs(area) <= 1e-14 * scale) {
      ++d.degenerate_faces;
    } else if (area < 0) {
      ++d.flipped_faces;
    }
  }
  return d;
}

}  // namespace ricci
