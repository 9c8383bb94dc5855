#pragma once
/// \file
/// Generated meshes of the kinds that break fragile methods on real data: CAD tessellations
/// (long strips and fans: valence 3 and angles of a tenth of a degree), valence-3 vertices, and
/// scan-like needles. The robustness tests and benchmarks run on them, next to the shared meshes.

#include <cstdint>

#include "ricci/mesh/mesh.hpp"

namespace ricci {

/// A closed cylinder (radius 1, the given height, genus 0) tessellated as a CAD exporter does:
/// the side is one strip of 2 `segments` triangles spanning its whole height, each cap a fan
/// from one of its rim vertices. Fan centres have valence segments + 1, other rim vertices 4 or
/// 5 (valence 3 at the fan's far ends); cap angles go down to about 180 / segments degrees, side
/// angles to about atan(2 pi / (segments height)).
/// \throw InvalidInput when segments < 3 or height is not finite and > 0
Mesh make_cad_cylinder(int segments, double height = 2.0);

/// A CAD-style ring (genus 1): a square-section torus of revolution whose four walls are strips of
/// 2 `segments` triangles each, every triangle spanning a whole wall.
/// \throw InvalidInput when segments < 3
Mesh make_cad_ring(int segments);

/// A ball with long thin fingers, closed and genus 0: the unit sphere tessellated as a cube
/// (`resolution` by `resolution` cells per side, each cut into two triangles, the vertices pushed
/// onto the sphere), with up to six fingers, one at the centre of each of the first `fingers`
/// sides (+x, +y, +z, -x, -y, -z). A finger replaces a block of 2 by 2 cells: a tube of
/// octagonal section (radius about 2.4 / resolution, as wide as the block) standing on the
/// block's boundary, `aspect` times as long as its circumference, in rings of near-square cells,
/// capped by the block's eight triangles. A conformal map squeezes a tube of circumference C by
/// about exp(-2 pi z / C) in length at depth z, so the tips' area comes out near
/// exp(-4 pi aspect) of the ball's scale (aspect 4: about e^-50). Each finger has
/// m = round(8 aspect) rings: 6 resolution^2 + 2 + 8 m fingers vertices, 12 resolution^2 +
/// 16 m fingers faces.
/// \throw InvalidInput when fingers is not in [0, 6], resolution is odd or below 4, or aspect is
///        not finite and > 0
Mesh make_ball_with_fingers(int fingers, double aspect, int resolution = 16);

/// Splits every `stride`-th face 1-to-3 at a point near its first corner (barycentric weights
/// 1 - 2 weight, weight, weight), lifted along the face normal by `lift` times the square root
/// of the face's area: each split adds a valence-3 vertex and two needles.
/// \throw InvalidInput when weight is not in (0, 1/3], stride < 1 or lift is not finite
Mesh split_faces_near_corner(const Mesh& mesh, double weight, double lift, int stride = 1);

/// Scan-like needles: an independent set of vertices (no two adjacent, every `stride`-th
/// candidate) each moved a random fraction, up to `amount`, of the way towards a random
/// neighbour. amount 0.998 makes corner angles of about a tenth of a degree. Deterministic for
/// a seed; boundary vertices stay.
/// \throw InvalidInput when amount is not in [0, 1) or stride < 1
Mesh pull_vertices_to_neighbours(const Mesh& mesh, double amount, std::uint32_t seed,
                                 int stride = 1);

}  // namespace ricci
