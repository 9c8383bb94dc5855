#include <Eigen/Geometry>
#include <cstdint>
#include <ostream>
#include <string>

#include "mesh/io/detail/binary_output.hpp"
#include "mesh/io/detail/writers.hpp"
#include "ricci/mesh/io.hpp"

namespace ricci::io_detail {

void write_stl(const std::string& path, const Mesh& mesh) {
  write_file_atomically(path, [&](std::ostream& stream) {
    BlockOutput out(stream);
    // The 80-byte header must not start with "solid", which would mark ASCII STL.
    std::string& bytes = out.bytes();
    bytes = "binary STL written by ricci";
    bytes.resize(80, ' ');
    append_little_endian(bytes, static_cast<std::uint32_t>(mesh.num_faces()));
    for (int f = 0; f < mesh.num_faces(); ++f) {
      Eigen::Vector3f corner[3];
      for (int k = 0; k < 3; ++k) {
        corner[k] = mesh.positions.row(mesh.triangles(f, k)).transpose().cast<float>();
      }
      Eigen::Vector3f normal = (corner[1] - corner[0]).cross(corner[2] - corner[0]);
      normal = normal.norm() > 0 ? Eigen::Vector3f(normal.normalized()) : Eigen::Vector3f::Zero();
      for (int k = 0; k < 3; ++k) append_little_endian(bytes, normal[k]);
      for (const Eigen::Vector3f& p : corner) {
        for (int k = 0; k < 3; ++k) append_little_endian(bytes, p[k]);
      }
      append_little_endian(bytes, std::uint16_t{0});  // attribute byte count
      out.end_of_item();
    }
  });
}

}  // namespace ricci::io_detail
