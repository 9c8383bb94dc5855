#include <cstdint>
#include <ostream>
#include <string>

#include "binary_output.hpp"
#include "ricci/mesh/io.hpp"
#include "writers.hpp"

namespace ricci::io_detail {

void write_ply(const std::string& path, const Mesh& mesh) {
  write_file_atomically(path, [&](std::ostream& out) {
    std::string bytes =
        "ply\nformat binary_little_endian 1.0\ncomment written by ricci\n"
        "element vertex " +
        std::to_string(mesh.num_vertices()) +
        "\nproperty double x\nproperty double y\nproperty double z\n"
        "element face " +
        std::to_string(mesh.num_faces()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    auto flush_if_large = [&] {
      if (bytes.size() < (1u << 20)) return;
      out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
      bytes.clear();
    };
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      for (int k = 0; k < 3; ++k) append_little_endian(bytes, mesh.positions(v, k));
      flush_if_large();
    }
    for (int f = 0; f < mesh.num_faces(); ++f) {
      append_little_endian(bytes, std::uint8_t{3});
      for (int k = 0; k < 3; ++k) append_little_endian(bytes, std::int32_t{mesh.triangles(f, k)});
      flush_if_large();
    }
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  });
}

}  // namespace ricci::io_detail
