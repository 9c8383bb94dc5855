#include <algorithm>
#include <cstdint>
#include <ostream>
#include <string>

#include "mesh/io/detail/binary_output.hpp"
#include "mesh/io/detail/writers.hpp"
#include "ricci/mesh/io.hpp"

namespace ricci::io_detail {

void write_ply(const std::string& path, const Mesh& mesh, const Polygons& polygons) {
  int largest = 3;
  for (int p = 0; p < polygons.num_polygons(); ++p) largest = std::max(largest, polygons.size(p));
  const bool int_counts = largest > 255;
  write_file_atomically(path, [&](std::ostream& stream) {
    BlockOutput out(stream);
    out.bytes() =
        "ply\nformat binary_little_endian 1.0\ncomment written by ricci\nelement vertex " +
        std::to_string(mesh.num_vertices()) +
        "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
        std::to_string(polygons.empty() ? mesh.num_faces() : polygons.num_polygons()) +
        "\nproperty list " + (int_counts ? "int" : "uchar") + " int vertex_indices\nend_header\n";
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      for (int k = 0; k < 3; ++k) append_little_endian(out.bytes(), mesh.positions(v, k));
      out.end_of_item();
    }
    auto count = [&](int n) {
      if (int_counts) {
        append_little_endian(out.bytes(), std::int32_t{n});
      } else {
        append_little_endian(out.bytes(), static_cast<std::uint8_t>(n));
      }
    };
    for (int p = 0; p < polygons.num_polygons(); ++p) {
      count(polygons.size(p));
      for (int i = polygons.corner_start[p]; i < polygons.corner_start[p + 1]; ++i) {
        const int c = polygons.corners[i];
        append_little_endian(out.bytes(), std::int32_t{mesh.triangles(c / 3, c % 3)});
      }
      out.end_of_item();
    }
    for (int f = 0; polygons.empty() && f < mesh.num_faces(); ++f) {
      count(3);
      for (int k = 0; k < 3; ++k) {
        append_little_endian(out.bytes(), std::int32_t{mesh.triangles(f, k)});
      }
      out.end_of_item();
    }
  });
}

}  // namespace ricci::io_detail
