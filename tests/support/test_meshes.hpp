#pragma once
/// \file
/// The generated meshes every property test runs over: one per topology class the issue names.

#include <string>
#include <vector>

#include "ricci/mesh/generate.hpp"

namespace ricci::testing {

struct NamedMesh {
  std::string name;
  Mesh mesh;
};

/// Small generated meshes: tetrahedron, icosphere, flat and curved disks, torus, closed genus 2
/// and 3, a sphere with holes and a genus-1 surface with holes.
inline std::vector<NamedMesh> generated_meshes() {
  return {
      {"tetrahedron", make_tetrahedron(1.0)},
      {"icosphere", make_icosphere(2)},
      {"flat_disk", make_disk(5)},
      {"curved_disk", make_disk(5, 0.6)},
      {"torus", make_torus(24, 12)},
      {"genus2", make_closed_surface(2, 10)},
      {"genus3", make_closed_surface(3, 10)},
      {"sphere_with_3_holes", make_surface_with_holes(0, 3, 10)},
      {"torus_with_2_holes", make_surface_with_holes(1, 2, 10)},
  };
}

}  // namespace ricci::testing
