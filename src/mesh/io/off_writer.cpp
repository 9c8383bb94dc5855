#include <cstdio>
#include <ostream>
#include <string>

#include "ricci/mesh/io.hpp"
#include "writers.hpp"

namespace ricci::io_detail {

void write_off(const std::string& path, const Mesh& mesh) {
  write_file_atomically(path, [&](std::ostream& out) {
    std::string text = "OFF\n" + std::to_string(mesh.num_vertices()) + " " +
                       std::to_string(mesh.num_faces()) + " 0\n";
    char buffer[96];
    auto append = [&](int n) {
      text.append(buffer, static_cast<std::size_t>(n));
      if (text.size() < (1u << 20)) return;
      out.write(text.data(), static_cast<std::streamsize>(text.size()));
      text.clear();
    };
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      append(std::snprintf(buffer, sizeof buffer, "%.17g %.17g %.17g\n", mesh.positions(v, 0),
                           mesh.positions(v, 1), mesh.positions(v, 2)));
    }
    for (int f = 0; f < mesh.num_faces(); ++f) {
      append(std::snprintf(buffer, sizeof buffer, "3 %d %d %d\n", mesh.triangles(f, 0),
                           mesh.triangles(f, 1), mesh.triangles(f, 2)));
    }
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
  });
}

}  // namespace ricci::io_detail
