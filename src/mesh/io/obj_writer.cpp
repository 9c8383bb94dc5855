#include <cstdio>
#include <ostream>
#include <string>

#include "ricci/mesh/io.hpp"
#include "writers.hpp"

namespace ricci {

void write_obj(const std::string& path, const Mesh& mesh) {
  write_file_atomically(path, [&](std::ostream& stream) {
    io_detail::BlockOutput out(stream);
    char line[96];
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      out.append(line,
                 std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", mesh.positions(v, 0),
                               mesh.positions(v, 1), mesh.positions(v, 2)));
    }
    for (int f = 0; f < mesh.num_faces(); ++f) {
      out.append(line, std::snprintf(line, sizeof line, "f %d %d %d\n", mesh.triangles(f, 0) + 1,
                                     mesh.triangles(f, 1) + 1, mesh.triangles(f, 2) + 1));
    }
  });
}

namespace {

/// write_obj with texture coordinates of `Columns` components (2: u v; 3: u v w).
template <int Columns>
void write_obj_with_vt(const std::string& path, const Mesh& mesh, const Triangles& uv_triangles,
                       const Eigen::Matrix<double, Eigen::Dynamic, Columns>& uv,
                       const ObjMaterial& material) {
  io_detail::check_faces("write_obj", path, mesh, &uv_triangles, uv);

  write_file_atomically(path, [&](std::ostream& stream) {
    io_detail::BlockOutput out(stream);
    char line[160];
    if (!material.library.empty()) {
      const std::string statement = "mtllib " + material.library + "\n";
      out.append(statement.data(), static_cast<int>(statement.size()));
    }
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      out.append(line,
                 std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", mesh.positions(v, 0),
                               mesh.positions(v, 1), mesh.positions(v, 2)));
    }
    for (Eigen::Index t = 0; t < uv.rows(); ++t) {
      if constexpr (Columns == 2) {
        out.append(line, std::snprintf(line, sizeof line, "vt %.17g %.17g\n", uv(t, 0), uv(t, 1)));
      } else {
        out.append(line, std::snprintf(line, sizeof line, "vt %.17g %.17g %.17g\n", uv(t, 0),
                                       uv(t, 1), uv(t, 2)));
      }
    }
    if (!material.library.empty()) {
      const std::string statement = "usemtl " + material.name + "\n";
      out.append(statement.data(), static_cast<int>(statement.size()));
    }
    for (int f = 0; f < mesh.num_faces(); ++f) {
      out.append(line, std::snprintf(line, sizeof line, "f %d/%d %d/%d %d/%d\n",
                                     mesh.triangles(f, 0) + 1, uv_triangles(f, 0) + 1,
                                     mesh.triangles(f, 1) + 1, uv_triangles(f, 1) + 1,
                                     mesh.triangles(f, 2) + 1, uv_triangles(f, 2) + 1));
    }
  });
}

}  // namespace

void write_obj(const std::string& path, const Mesh& mesh, const Triangles& uv_triangles,
               const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv, const ObjMaterial& material) {
  write_obj_with_vt(path, mesh, uv_triangles, uv, material);
}

void write_obj(const std::string& path, const Mesh& mesh, const Triangles& uvw_triangles,
               const Eigen::Matrix<double, Eigen::Dynamic, 3>& uvw, const ObjMaterial& material) {
  write_obj_with_vt(path, mesh, uvw_triangles, uvw, material);
}

}  // namespace ricci
