#include <cstdio>
#include <ostream>
#include <string>

#include "ricci/mesh/io.hpp"
#include "writers.hpp"

namespace ricci {

void write_obj(const std::string& path, const Mesh& mesh) {
  write_file_atomically(path, [&](std::ostream& out) {
    std::string text;
    char buffer[96];
    auto flush_if_large = [&] {
      if (text.size() < (1u << 20)) return;
      out.write(text.data(), static_cast<std::streamsize>(text.size()));
      text.clear();
    };
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const int n = std::snprintf(buffer, sizeof buffer, "v %.17g %.17g %.17g\n",
                                  mesh.positions(v, 0), mesh.positions(v, 1), mesh.positions(v, 2));
      text.append(buffer, static_cast<std::size_t>(n));
      flush_if_large();
    }
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const int n = std::snprintf(buffer, sizeof buffer, "f %d %d %d\n", mesh.triangles(f, 0) + 1,
                                  mesh.triangles(f, 1) + 1, mesh.triangles(f, 2) + 1);
      text.append(buffer, static_cast<std::size_t>(n));
      flush_if_large();
    }
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
  });
}

namespace {

/// write_obj with texture coordinates of `Columns` components (2: u v; 3: u v w).
template <int Columns>
void write_obj_with_vt(const std::string& path, const Mesh& mesh, const Triangles& uv_triangles,
                       const Eigen::Matrix<double, Eigen::Dynamic, Columns>& uv,
                       const ObjMaterial& material) {
  io_detail::check_faces("write_obj", path, mesh, &uv_triangles, uv);

  write_file_atomically(path, [&](std::ostream& out) {
    std::string text;
    char buffer[160];
    auto append = [&](int n) {
      text.append(buffer, static_cast<std::size_t>(n));
      if (text.size() < (1u << 20)) return;
      out.write(text.data(), static_cast<std::streamsize>(text.size()));
      text.clear();
    };
    if (!material.library.empty()) text += "mtllib " + material.library + "\n";
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      append(std::snprintf(buffer, sizeof buffer, "v %.17g %.17g %.17g\n", mesh.positions(v, 0),
                           mesh.positions(v, 1), mesh.positions(v, 2)));
    }
    for (Eigen::Index t = 0; t < uv.rows(); ++t) {
      if constexpr (Columns == 2) {
        append(std::snprintf(buffer, sizeof buffer, "vt %.17g %.17g\n", uv(t, 0), uv(t, 1)));
      } else {
        append(std::snprintf(buffer, sizeof buffer, "vt %.17g %.17g %.17g\n", uv(t, 0), uv(t, 1),
                             uv(t, 2)));
      }
    }
    if (!material.library.empty()) text += "usemtl " + material.name + "\n";
    for (int f = 0; f < mesh.num_faces(); ++f) {
      append(std::snprintf(buffer, sizeof buffer, "f %d/%d %d/%d %d/%d\n", mesh.triangles(f, 0) + 1,
                           uv_triangles(f, 0) + 1, mesh.triangles(f, 1) + 1, uv_triangles(f, 1) + 1,
                           mesh.triangles(f, 2) + 1, uv_triangles(f, 2) + 1));
    }
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
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
