#pragma once
/// \file
/// A polygon mesh's layout as a file holds it. The layout is computed on the triangles; a file
/// writes each polygon with one uv per corner (`f v/vt v/vt v/vt v/vt`), and whoever reads it
/// splits the polygon again, as the fan from its first corner. Where the polygon's layout is not
/// convex that fan can fold although the triangles computed did not, so the polygon is written
/// from a corner whose fan is drawn unflipped (the same face: same corners in the same cyclic
/// order), and the distortion figures are those of the fans written.

#include <Eigen/Core>

#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/polygons.hpp"
#include "ricci/param/distortion.hpp"

namespace ricci {

/// The polygons with each one's corners listed from a corner whose fan has no triangle drawn
/// flipped or flat in the layout (signed uv area <= 0), the fewest of zero area in R^3 among
/// those; the first such corner (the polygon's own first corner when its fan is sound). A
/// polygon no corner's fan is sound from (not star-shaped from a corner in the layout: wallhole's
/// two 11-gons) is given as its own triangles, one polygon each, after the polygons before it:
/// the result then has more polygons than the input. O(n) per polygon whose fan from its first
/// corner is sound, O(n^2) at worst.
/// \param mesh 3D positions (#V by 3) and triangles (#F by 3)
/// \param uv_triangles #F by 3 indices into uv (corner c of triangle t at uv.row(uv_triangles(t,
///        c)))
/// \param uv #UV by 2 layout positions
/// \pre polygons passes check_polygons for mesh.triangles (an empty one comes back empty)
Polygons start_fans_where_valid(const Polygons& polygons, const Mesh& mesh,
                                const Triangles& uv_triangles,
                                const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv);

/// measure_distortion of the layout as a file of these polygons holds it: on the fan of every
/// polygon from its first corner (polygon_fans), as a reader of the file splits it; on the
/// triangles themselves when polygons is empty. Fan triangles of zero area in R^3 (a polygon
/// with three corners in a line) have no distortion: they count only as flipped or degenerate
/// faces, by their signed uv area.
/// \throw InvalidInput as measure_distortion
Distortion measure_polygon_distortion(const Mesh& mesh, const Polygons& polygons,
                                      const Triangles& uv_triangles,
                                      const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv);

}  // namespace ricci
