#include <cstdio>
#include <ostream>
#include <string>

#include "mesh/io/detail/writers.hpp"
#include "ricci/mesh/io.hpp"

namespace ricci::io_detail {

void write_off(const std::string& path, const Mesh& mesh, const Polygons& polygons) {
  write_file_atomically(path, [&](std::ostream& stream) {
    BlockOutput out(stream);
    const std::string header =
        "OFF\n" + std::to_string(mesh.num_vertices()) + " " +
        std::to_string(polygons.empty() ? mesh.num_faces() : polygons.num_polygons()) + " 0\n";
    out.append(header.data(), static_cast<int>(header.size()));
    char line[96];
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      out.append(line, std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", mesh.positions(v, 0),
                                     mesh.positions(v, 1), mesh.positions(v, 2)));
    }
    for (int f = 0; polygons.empty() && f < mesh.num_faces(); ++f) {
      out.append(line, std::snprintf(line, sizeof line, "3 %d %d %d\n", mesh.triangles(f, 0),
                                     mesh.triangles(f, 1), mesh.triangles(f, 2)));
    }
    for (int p = 0; p < polygons.num_polygons(); ++p) {
      out.append(line, std::snprintf(line, sizeof line, "%d", polygons.size(p)));
      for (int i = polygons.corner_start[p]; i < polygons.corner_start[p + 1]; ++i) {
        const int c = polygons.corners[i];
        out.append(line, std::snprintf(line, sizeof line, " %d", mesh.triangles(c / 3, c % 3)));
      }
      out.append("\n", 1);
    }
  });
}

}  // namespace ricci::io_detail
