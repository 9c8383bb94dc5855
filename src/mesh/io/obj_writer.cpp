#include <ostream>
#include <string>

#include "mesh/io/detail/writers.hpp"
#include "ricci/mesh/io.hpp"

namespace ricci {
namespace io_detail {
namespace {

/// An OBJ file: `mtllib`, `v`, `vt` with `Columns` components (2: u v; 3: u v w; none without
/// uv_triangles), `usemtl`, then `f` per triangle, or per polygon when polygons is not empty.
template <int Columns>
void write_obj_file(const std::string& path, const Mesh& mesh, const Triangles* uv_triangles,
                    const Eigen::Matrix<double, Eigen::Dynamic, Columns>& uv,
                    const ObjMaterial& material, const Polygons& polygons) {
  write_file_atomically(path, [&](std::ostream& stream) {
    BlockOutput out(stream);
    const bool textured = uv_triangles != nullptr;
    if (textured && !material.library.empty()) {
      const std::string statement = "mtllib " + material.library + "\n";
      out.append(statement.data(), static_cast<int>(statement.size()));
    }
    // (Numbers by std::to_chars, shortest round trip: the same doubles as %.17g read back,
    // written several times faster.)
    append_lines(out, mesh.num_vertices(), [&](int v, std::string& bytes) {
      append_number_line(bytes, "v ", mesh.positions.row(v));
    });
    if (textured) {
      append_lines(out, static_cast<int>(uv.rows()),
                   [&](int t, std::string& bytes) { append_number_line(bytes, "vt ", uv.row(t)); });
    }
    if (textured && !material.library.empty()) {
      const std::string statement = "usemtl " + material.name + "\n";
      out.append(statement.data(), static_cast<int>(statement.size()));
    }
    // One corner " v" or " v/vt" (1-based).
    auto corner = [&](int f, int k, std::string& bytes) {
      bytes.push_back(' ');
      append_integer(bytes, mesh.triangles(f, k) + 1);
      if (textured) {
        bytes.push_back('/');
        append_integer(bytes, (*uv_triangles)(f, k) + 1);
      }
    };
    if (polygons.empty()) {
      append_lines(out, mesh.num_faces(), [&](int f, std::string& bytes) {
        bytes.push_back('f');
        for (int k = 0; k < 3; ++k) corner(f, k, bytes);
        bytes.push_back('\n');
      });
      return;
    }
    append_lines(out, polygons.num_polygons(), [&](int p, std::string& bytes) {
      bytes.push_back('f');
      for (int i = polygons.corner_start[p]; i < polygons.corner_start[p + 1]; ++i) {
        corner(polygons.corners[i] / 3, polygons.corners[i] % 3, bytes);
      }
      bytes.push_back('\n');
    });
  });
}

}  // namespace

void write_obj_faces(const std::string& path, const TexturedMesh& mesh,
                     const ObjMaterial& material) {
  if (!mesh.has_uv()) {
    write_obj_file<2>(path, mesh.mesh, nullptr, {}, material, mesh.polygons);
  } else if (mesh.uv_weights.size() == 0) {
    write_obj_file<2>(path, mesh.mesh, &mesh.uv_triangles, mesh.uv, material, mesh.polygons);
  } else {
    // Back to the homogeneous coordinates the reader divided by w.
    Eigen::Matrix<double, Eigen::Dynamic, 3> uvw(mesh.uv.rows(), 3);
    uvw.leftCols<2>() = mesh.uv.array().colwise() * mesh.uv_weights.array();
    uvw.col(2) = mesh.uv_weights;
    write_obj_file<3>(path, mesh.mesh, &mesh.uv_triangles, uvw, material, mesh.polygons);
  }
}

}  // namespace io_detail

void write_obj(const std::string& path, const Mesh& mesh) {
  io_detail::write_obj_file<2>(path, mesh, nullptr, {}, {}, {});
}

void write_obj(const std::string& path, const Mesh& mesh, const Triangles& uv_triangles,
               const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv, const ObjMaterial& material) {
  io_detail::check_faces("write_obj", path, mesh, &uv_triangles, uv);
  io_detail::write_obj_file(path, mesh, &uv_triangles, uv, material, {});
}

void write_obj(const std::string& path, const Mesh& mesh, const Triangles& uvw_triangles,
               const Eigen::Matrix<double, Eigen::Dynamic, 3>& uvw, const ObjMaterial& material) {
  io_detail::check_faces("write_obj", path, mesh, &uvw_triangles, uvw);
  io_detail::write_obj_file(path, mesh, &uvw_triangles, uvw, material, {});
}

}  // namespace ricci
