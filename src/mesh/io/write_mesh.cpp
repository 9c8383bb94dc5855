#include <cmath>
#include <string>

#include "mesh/io/detail/writers.hpp"
#include "ricci/errors.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/mesh/polygons.hpp"

namespace ricci {
namespace io_detail {

void check_faces(const std::string& function, const std::string& path, const Mesh& mesh,
                 const Triangles* uv_triangles, const Eigen::Ref<const Eigen::MatrixXd>& uv) {
  auto invalid = [&](const std::string& what) {
    throw InvalidInput(function + ": " + path + ": " + what);
  };
  if (uv_triangles != nullptr && uv_triangles->rows() != mesh.num_faces()) {
    invalid("uv_triangles has " + std::to_string(uv_triangles->rows()) + " rows but the mesh has " +
            std::to_string(mesh.num_faces()) + " faces");
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.triangles(f, c);
      if (v < 0 || v >= mesh.num_vertices()) {
        invalid("face " + std::to_string(f) + " corner " + std::to_string(c) + ": vertex index " +
                std::to_string(v) + " is out of range [0, " + std::to_string(mesh.num_vertices()) +
                ")");
      }
      if (uv_triangles == nullptr) continue;
      const int t = (*uv_triangles)(f, c);
      if (t < 0 || t >= uv.rows()) {
        invalid("face " + std::to_string(f) + " corner " + std::to_string(c) + ": uv index " +
                std::to_string(t) + " is out of range [0, " + std::to_string(uv.rows()) + ")");
      }
    }
  }
  for (Eigen::Index t = 0; t < uv.rows(); ++t) {
    if (!uv.row(t).allFinite()) invalid("uv row " + std::to_string(t) + " is not finite");
  }
}

}  // namespace io_detail

namespace {

const char* format_name(MeshFormat format) {
  switch (format) {
    case MeshFormat::Obj:
      return "OBJ";
    case MeshFormat::Off:
      return "OFF";
    case MeshFormat::Ply:
      return "PLY";
    case MeshFormat::Stl:
      return "STL";
    case MeshFormat::Glb:
      return "glTF binary";
  }
  return "?";
}

/// write_mesh's checks beyond check_faces: finite positions, one positive weight per uv row.
void check_positions_and_weights(const std::string& path, const TexturedMesh& textured) {
  auto invalid = [&](const std::string& what) {
    throw InvalidInput("write_mesh: " + path + ": " + what);
  };
  for (int v = 0; v < textured.mesh.num_vertices(); ++v) {
    if (!textured.mesh.positions.row(v).allFinite()) {
      invalid("vertex " + std::to_string(v) + " has a coordinate that is not finite");
    }
  }
  const Eigen::VectorXd& w = textured.uv_weights;
  if (w.size() != 0 && w.size() != textured.uv.rows()) {
    invalid("uv_weights has " + std::to_string(w.size()) + " entries for " +
            std::to_string(textured.uv.rows()) + " uv rows");
  }
  for (Eigen::Index t = 0; t < w.size(); ++t) {
    if (!(std::isfinite(w[t]) && w[t] > 0)) {
      invalid("uv weight " + std::to_string(t) + " is not a positive number");
    }
  }
}

}  // namespace

void write_mesh(const std::string& path, const TexturedMesh& mesh, const WriteOptions& options) {
  const MeshFormat format = options.format ? *options.format : format_from_path(path);
  io_detail::check_faces("write_mesh", path, mesh.mesh,
                         mesh.has_uv() ? &mesh.uv_triangles : nullptr, mesh.uv);
  check_positions_and_weights(path, mesh);
  check_polygons(mesh.polygons, mesh.mesh.triangles, "write_mesh: " + path);
  auto invalid = [&](const std::string& what) {
    throw InvalidInput("write_mesh: " + path + ": " + what);
  };
  if (!options.material.library.empty() && (format != MeshFormat::Obj || !mesh.has_uv())) {
    invalid(
        "a material (WriteOptions::material) is written only into OBJ with texture "
        "coordinates");
  }
  if (mesh.has_uv() && !options.drop_uv &&
      (format == MeshFormat::Off || format == MeshFormat::Ply || format == MeshFormat::Stl)) {
    throw InvalidInput("write_mesh: " + path + ": " + format_name(format) +
                           " cannot hold texture coordinates: write OBJ or glTF binary, or set "
                           "WriteOptions::drop_uv to write the mesh without them",
                       fixes_of({{"drop_uv", "true"}}));
  }
  switch (format) {
    case MeshFormat::Obj:
      io_detail::write_obj_faces(path, mesh, options.material);
      return;
    case MeshFormat::Off:
      io_detail::write_off(path, mesh.mesh, mesh.polygons);
      return;
    case MeshFormat::Ply:
      io_detail::write_ply(path, mesh.mesh, mesh.polygons);
      return;
    case MeshFormat::Stl:
      io_detail::write_stl(path, mesh.mesh);
      return;
    case MeshFormat::Glb:
      if (!options.glb_writer) {
        invalid(
            "glTF binary is written by the picture library (ricci_render, built with tinygltf): "
            "set WriteOptions::glb_writer to its glb_writer() (ricci/render/textured_files.hpp)");
      }
      if (!mesh.has_uv()) invalid("glTF binary needs texture coordinates");
      options.glb_writer(path, mesh);
      return;
  }
  invalid("unknown mesh format");
}

}  // namespace ricci
