"""Spherical conformal map: ``sphere`` wraps ``sphere_map`` (ricci/sphere/sphere.hpp)."""

import copy

from . import _arrays, _ricci
from ._flow import set_fields, set_structure_and_solver


def sphere(V, F, *, scheme=None, pole=None, flips=None, tolerance=None, max_iterations=None,
           packing_init=None, max_intersection_angle=None, centre_tolerance=None,
           max_centre_iterations=None, untangle=None, progress=None, options=None):
    """Conformal map of a closed genus-0 mesh onto the unit sphere (docs/sphere.md): the pole
    vertex and its star are removed, the disk left is flattened by the Ricci flow with a
    circular boundary, projected stereographically, and a Moebius transformation puts the
    centre of mass of the input's area at the origin.

    V: (n, 3) float positions; F: (m, 3) integer counter-clockwise triangles, one closed
    genus-0 component.

    scheme: the disk's discrete metric (``"vertex-scaling"``, the default, ``"thurston"``,
      ``"tangential"``, ``"inversive-distance"``, ``"virtual-radius"``).
    pole: vertex removed for the flow (default: choose_pole_vertex, the vertex whose link keeps
      the angles the disk's boundary asks for).
    flips, tolerance (1e-12), max_iterations, packing_init, max_intersection_angle, progress:
      as ``ricci.flow``.
    centre_tolerance (1e-12), max_centre_iterations (100): the Moebius normalisation.
    untangle (True): move the vertices of faces the map inverts into their stars' cones.
    options: a ``SphereOptions`` to start from (copied); other arguments override its fields.

    Returns a ``SphereResult``: converged, valid, message, positions (n, 3) on the unit sphere
    (the faces are F), pole, the invariants (max_radius_deviation, inverted_faces,
    inverted_by_rounding, spherical_area, centre_of_mass, inverted_pole_faces), the precision
    (precision_bits, min_plane_altitude, min_sphere_altitude, unresolved_faces), the
    untangling (untangled_vertices, max_untangle_move), the distortion (angle_distortion_mean /
    p95 / max, angle_error_mean / max, log_area_min / max / mean / stddev: how far the
    conformal factor reaches), the normalisation (centre_iterations, initial_centre) and the
    disk's flow (a MeshFlowResult). When the flow does not converge, converged is False; when
    the map keeps an inverted face or a figure is not finite, valid is False; message says why
    (nothing is raised).

    Raises ValueError for arrays of the wrong shape or dtype, InvalidInput for a mesh that is
    not one closed genus-0 component or a pole out of range, TopologyError for non-manifold
    meshes.
    """
    mesh = _arrays.mesh(V, F)
    opts = _ricci.SphereOptions() if options is None else copy.copy(options)
    set_fields(opts, pole=pole, centre_tolerance=centre_tolerance,
               max_centre_iterations=max_centre_iterations, untangle=untangle)
    set_structure_and_solver(opts, scheme=scheme, packing_init=packing_init,
                             max_intersection_angle=max_intersection_angle, fit_sweeps=None,
                             fit_tolerance=None, solver=None, tolerance=tolerance,
                             max_iterations=max_iterations, gradient_step=None, armijo=None,
                             max_backtracks=None, use_cholmod=None,
                             reuse_factorization_cg_iterations=None, progress=progress,
                             flips=flips)
    return _ricci.sphere_map(mesh, opts)
