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
    for (int v = 0; v < mesh.num_vertices(); ++v) out.number_line("", mesh.positions.row(v));
    for (int f = 0; polygons.empty() && f < mesh.num_faces(); ++f) {
      out.text("3");
      for (int k = 0; k < 3; ++k) {
        out.text(" ");
        out.integer(mesh.triangles(f, k));
      }
      out.text("\n");
      out.end_of_item();
    }
    for (int p = 0; p < polygons.num_polygons(); ++p) {
      out.integer(polygons.size(p));
      for (int i = polygons.corner_start[p]; i < polygons.corner_start[p + 1]; ++i) {
        const int c = polygons.corners[i];
        out.text(" ");
        out.integer(mesh.triangles(c / 3, c % 3));
      }
      out.text("\n");
      out.end_of_item();
    }
  });
}

}  // namespace ricci::io_detail
