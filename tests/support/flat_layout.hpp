#pragma once
/// \file
/// A mesh flattened the way the layout and atlas tests need it: a flat metric with cones, a cut
/// graph through the cones, the mesh sliced along it and laid out in the plane.

#include <complex>
#include <vector>

#include <gtest/gtest.h>

#include "ricci/flow/mesh_flow.hpp"
#include "ricci/mesh/mesh.hpp"
#include "ricci/metric/lengths.hpp"
#include "ricci/metric/scheme.hpp"
#include "ricci/param/cut/cut_graph.hpp"
#include "ricci/param/layout/layout.hpp"

namespace ricci::testing {

/// Row v of the layout's uv as a complex number.
inline std::complex<double> uv_of(const Layout& layout, int v) {
  return {layout.uv(v, 0), layout.uv(v, 1)};
}

/// The flat metric of `scheme` with `cones` and the given boundary condition; expects it to
/// converge.
inline MeshFlowResult flat_flow(const Mesh& mesh, BoundaryMode boundary,
                                Scheme scheme = Scheme::Thurston,
                                const std::vector<Cone>& cones = {}) {
  MeshFlowOptions options;
  options.structure.scheme = scheme;
  options.target.kind = TargetKind::Flat;
  options.target.boundary = boundary;
  options.target.cones = cones;
  // The layout closes up around an interior vertex only as well as the metric is flat there: a
  // curvature residual d leaves a misclosure of about d times the distance to the root, summed
  // over the vertices the two tree paths enclose. At the default 1e-10 that reaches 2e-9 of an
  // edge on punctured-torus.obj; Newton gets to 1e-12 in one more step, and then the layout's
  // own rounding is what the tests' 1e-9 bounds measure.
  options.flow.tolerance = 1e-12;
  MeshFlowResult result = flow_mesh(mesh, options);
  EXPECT_TRUE(result.converged) << result.max_error;
  return result;
}

/// A flat metric, its cut, the sliced mesh and the layout.
struct Flattened {
  MeshFlowResult flow;
  CutGraph cut;
  CutMesh cut_mesh;
  Layout layout;
};

/// flat_flow, then a cut graph through the cones (on the input's edge lengths), the slice and
/// the layout.
inline Flattened flatten(const Mesh& mesh, BoundaryMode boundary,
                         const std::vector<Cone>& cones = {}, Scheme scheme = Scheme::Thurston) {
  Flattened out;
  out.flow = flat_flow(mesh, boundary, scheme, cones);
  CutGraphOptions cut_options;
  for (const Cone& cone : cones) cut_options.cones.push_back(cone.vertex);
  out.cut = cut_graph(out.flow.intrinsic.topology(),
                      input_edge_lengths(mesh, out.flow.intrinsic.topology()), cut_options);
  out.cut_mesh = slice(out.flow.intrinsic.topology(), out.cut);
  out.layout = layout_flat(out.flow.intrinsic.topology(), out.flow.lengths, out.cut, out.cut_mesh);
  return out;
}

}  // namespace ricci::testing
