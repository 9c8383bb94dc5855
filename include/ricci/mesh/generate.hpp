#pragma once
/// \file
/// Meshes generated in code, with known topology and, where possible, known geometry: the
/// built-in examples of the command line, the test meshes and the benchmark meshes.

#include "ricci/mesh/mesh.hpp"

namespace ricci {

/// Regular tetrahedron with the given edge length (4 vertices, 4 faces, chi = 2), centred at the
/// origin. Its curvature is pi at every vertex: the smallest analytic test of the flow.
/// \throw InvalidInput when edge_length is not finite and > 0
Mesh make_tetrahedron(double edge_length = 1.0);

/// Icosahedron subdivided `subdivisions` times, vertices projected on the sphere of `radius`
/// (10 * 4^s + 2 vertices, 20 * 4^s faces). Smallest corner angle above 54 degrees for every s.
/// \throw InvalidInput when subdivisions is outside [0, 12] or radius is not finite and > 0
Mesh make_icosphere(int subdivisions, double radius = 1.0);

/// Unit disk in the plane z = 0 meshed by `rings` concentric rings around a centre vertex, ring r
/// holding 6 r vertices (1 + 3 rings (rings + 1) vertices, 6 rings^2 faces, one boundary loop).
/// Between two rings the triangles follow the hexagonal lattice, so every interior vertex but the
/// centre has degree 6; smallest corner angle about 37 degrees for a flat disk.
/// \param bulge lifts the disk to the cap z = bulge (1 - x^2 - y^2), so that it is curved;
///        triangles stay counter-clockwise seen from +z
/// \throw InvalidInput when rings < 1 or bulge is not finite
Mesh make_disk(int rings, double bulge = 0.0);

/// Torus of revolution with radii R > r, meshed by a major x minor grid of quads split into
/// triangles (major * minor vertices, 2 * major * minor faces, chi = 0). Vertex (i, j) has index
/// i * minor + j and lies at major angle 2 pi i / major, minor angle 2 pi j / minor. All
/// diagonals run the same way, so every vertex has degree 6.
/// \throw InvalidInput when a segment count is < 3, a radius is not finite and > 0, or
///        minor_radius >= major_radius
Mesh make_torus(int major_segments, int minor_segments, double major_radius = 1.0,
                double minor_radius = 0.4);

/// A closed orientable surface of the given genus >= 0 (a thickened plate with `genus` holes,
/// smoothed), with about `resolution` quads along its length. chi = 2 - 2 genus.
/// Genus 0 is the unit cube; genus g >= 1 a plate of (2g+1) x 3 x 1 unit cubes from which the
/// cubes (2i+1, 1) are removed to make the tunnels; centred at the origin. Each unit cube is cut
/// into k^3 small cubes, k = round(resolution / columns) but at least 1 (columns = 1 for genus 0,
/// else 2g+1), and the boundary of the solid is meshed by their faces split along the shorter
/// diagonal. For k >= 2, a few steps of Taubin smoothing round its edges over about two cells, so
/// that the curvature is not all on the corners. Smallest corner angle above 37 degrees at every
/// resolution; one component, outward-oriented, free of self-intersections.
/// \throw InvalidInput when genus < 0, resolution < 1 or the face count overflows int
Mesh make_closed_surface(int genus, int resolution = 12);

/// A surface of the given genus with `holes` boundary loops cut into it (chi = 2 - 2g - holes):
/// make_closed_surface with at least 3 cubes per cell, from whose top face `holes` square
/// patches (about a third of a cell wide) are removed, spread out and away from its rim.
/// \throw InvalidInput as make_closed_surface, when holes < 0, or when the top face has no room
///        for that many holes at this resolution (the message says how many fit)
Mesh make_surface_with_holes(int genus, int holes, int resolution = 12);

/// Flat rectangular grid [0, width] x [0, height] of nx by ny quads split into triangles
/// ((nx+1) (ny+1) vertices, 2 nx ny faces, one boundary loop), at z = 0 exactly, counter-clockwise
/// seen from +z. Vertex (x, y) has index x + (nx+1) y.
/// \throw InvalidInput when nx or ny < 1 or width or height is not finite and > 0
Mesh make_grid(int nx, int ny, double width = 1.0, double height = 1.0);

}  // namespace ricci
