#include <cstdint>
#include <ostream>
#include <string>

#include "binary_output.hpp"
#include "ricci/mesh/io.hpp"
#include "writers.hpp"

namespace ricci::io_detail {

void write_ply(const std::string& path, const Mesh& mesh) {
  write_file_atomically(path, [&](std::ostream& stream) {
    BlockOutput out(stream);
    out.bytes() =
        "ply\nformat binary_little_endian 1.0\ncomment written by ricci\nelement vertex " +
        std::to_string(mesh.num_vertices()) +
        "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
        std::to_string(mesh.num_faces()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      for (int k = 0; k < 3; ++k) append_little_endian(out.bytes(), mesh.positions(v, k));
      out.end_of_item();
    }
    for (int f = 0; f < mesh.num_faces(); ++f) {
      append_little_endian(out.bytes(), std::uint8_t{3});
      for (int k = 0; k < 3; ++k) {
        append_little_endian(out.bytes(), std::int32_t{mesh.triangles(f, k)});
      }
      out.end_of_item();
    }
  });
}

}  // namespace ricci::io_detail
