#include <cstdio>
#include <ostream>
#include <string>

#include "ricci/mesh/io.hpp"
#include "writers.hpp"

namespace ricci::io_detail {

void write_off(const std::string& path, const Mesh& mesh) {
  write_file_atomically(path, [&](std::ostream& stream) {
    BlockOutput out(stream);
    const std::string header = "OFF\n" + std::to_string(mesh.num_vertices()) + " " +
                               std::to_string(mesh.num_faces()) + " 0\n";
    out.append(header.data(), static_cast<int>(header.size()));
    char line[96];
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      out.append(line, std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", mesh.positions(v, 0),
                                     mesh.positions(v, 1), mesh.positions(v, 2)));
    }
    for (int f = 0; f < mesh.num_faces(); ++f) {
      out.append(line, std::snprintf(line, sizeof line, "3 %d %d %d\n", mesh.triangles(f, 0),
                                     mesh.triangles(f, 1), mesh.triangles(f, 2)));
    }
  });
}

}  // namespace ricci::io_detail
