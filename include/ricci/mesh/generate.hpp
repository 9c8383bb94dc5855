#pragma once
/// \file
/// Meshes generated in code, with known topology and, where possible, known geometry: the
/// built-in examples of the command line, the test meshes and the benchmark meshes.

#include "ricci/mesh/mesh.hpp"

namespace ricci {

/// Regular tetrahedron with the given edge length (4 vertices, 4 faces, chi = 2).
Mesh make_tetrahedron(double edge_length = 1.0);

/// Icosahedron subdivided `subdivisions` times, vertices projected on the sphere of `radius`
/// (10 * 4^s + 2 vertices, 20 * 4^s faces).
Mesh make_icosphere(int subdivisions, double radius = 1.0);

/// Unit disk in the plane z = 0 meshed by `rings` concentric rings around a centre vertex, ring r
/// holding 6 r vertices (1 + 3 rings (rings + 1) vertices, 6 rings^2 faces, one boundary loop).
/// \param bulge lifts the disk to the cap z = bulge (1 - x^2 - y^2), so that it is curved
Mesh make_disk(int rings, double bulge = 0.0);

/// Torus of revolution with radii R > r, meshed by a major x minor grid of quads split into
/// triangles (major * minor vertices, 2 * major * minor faces, chi = 0).
Mesh make_torus(int major_segments, int minor_segments, double major_radius = 1.0,
                double minor_radius = 0.4);

/// A closed orientable surface of the given genus >= 0 (a thickened plate with `genus` holes,
/// smoothed), with about `resolution` quads along its length. chi = 2 - 2 genus.
Mesh make_closed_surface(int genus, int resolution = 12);

/// A surface of the given genus with `holes` boundary loops cut into it (chi = 2 - 2g - holes).
Mesh make_surface_with_holes(int genus, int holes, int resolution = 12);

/// Flat rectangular grid [0, width] x [0, height] of nx by ny quads split into triangles.
Mesh make_grid(int nx, int ny, double width = 1.0, double height = 1.0);

}  // namespace ricci
