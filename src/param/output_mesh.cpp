#include "ricci/param/output_mesh.hpp"

namespace ricci {

TexturedMesh textured_mesh(const Parameterization& result) {
  TexturedMesh textured;
  textured.mesh = result.mesh;
  if (result.uv.rows() > 0) {
    textured.uv_triangles = result.cut_mesh.triangles;
    textured.uv = result.uv;
    textured.polygons = result.polygons;
  }
  return textured;
}

}  // namespace ricci
