#pragma once
/// \file
/// Internal: the pipeline of parameterize on a mesh of one component (one_component.cpp), which
/// the public parameterize (parameterize.cpp) runs on the whole mesh or per component.

#include "ricci/param/parameterize.hpp"

namespace ricci {

/// The exact map on a single-component mesh: cones, flow, cut, layout, atlas, distortion.
/// \throw InvalidInput (bad cones, inadmissible target, not exactly one component), TopologyError
ParamResult parameterize_one_component(const Mesh& input, const ParamOptions& options);

/// The same with the mesh's connectivity at hand. \pre topology = build_topology(input)
ParamResult parameterize_one_component(const Mesh& input, const ParamOptions& options,
                                       Topology topology);

}  // namespace ricci
