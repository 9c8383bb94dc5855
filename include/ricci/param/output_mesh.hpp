#pragma once
/// \file
/// A parameterization as the textured mesh `ricci param` writes: the file is
/// write_mesh(path, textured_mesh(result)).

#include "ricci/mesh/textured_mesh.hpp"
#include "ricci/param/parameterize.hpp"

namespace ricci {

/// The parameterized mesh with its texture coordinates: mesh = result.mesh (positions #V by 3,
/// triangles #F by 3, edge-split vertices included), uv_triangles = result.cut_mesh.triangles
/// (#F by 3: corner c of face f has uv row uv_triangles(f, c); corners on either side of a seam
/// have different rows), uv = result.uv (#UV by 2, unit square), no homogeneous weights, and
/// polygons = result.polygons (a polygon mesh's faces, each written from a corner whose fan is
/// sound; empty: the triangles are the faces). A result without a layout (not converged, or
/// cancelled) gives empty uv, uv_triangles and polygons.
TexturedMesh textured_mesh(const Parameterization& result);

}  // namespace ricci
