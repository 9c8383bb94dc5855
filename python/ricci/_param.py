"""Global conformal parameterization: ``parameterize`` wraps the C++ pipeline."""

import copy
import numbers

import numpy as np

from . import _arrays, _ricci
from ._flow import cone_list, set_fields, set_structure_and_solver

_CONE_MODES = ("auto", "none", "one")


def parameterize(V, F, *, cones=None, boundary=None, quantize=None, max_log_scale=None,
                 max_cones=None, try_first_cone_candidates=None, modify_connectivity=None,
                 scheme=None, packing_init=None, max_intersection_angle=None, fit_sweeps=None,
                 fit_tolerance=None, solver=None, tolerance=None, max_iterations=None,
                 gradient_step=None, armijo=None, max_backtracks=None, use_cholmod=None,
                 reuse_factorization_cg_iterations=None, progress=None, flips=None, options=None):
    """Global conformal parameterization of a single-component manifold mesh: cones, valence
    raising, Ricci flow to a flat metric, cut graph, layout, atlas, distortion, uv in the unit
    square.

    V: (n, 3) float positions; F: (m, 3) integer counter-clockwise triangles.

    cones: ``"auto"`` (greedy selection until max_log_scale holds, the default), an int (that
      many automatic cones), ``"none"`` (a torus, or a surface with boundary), ``"one"`` (all
      of 2 pi chi at one vertex, genus >= 2), or user cones: ``[(vertex, curvature), ...]``,
      ``{vertex: curvature}`` or ``"V:K,V:K"`` (input vertex indices, radians or ``"pi/2"``).
    boundary: ``"free"`` (default), ``"disk"``, ``"disk-length"``.
    quantize: round cone curvatures to multiples of pi/2.
    Automatic cones (``ConeSelectionOptions``): max_log_scale (1.0), max_cones (64),
      try_first_cone_candidates (1).
    modify_connectivity: split edges around cones whose valence is too low (True).
    Metric and solver: as ``ricci.flow`` (tolerance defaults to 1e-12 here), flips included:
      after Delaunay flips the triangles returned are the intrinsic Delaunay triangulation of
      the input vertices.
    options: a ``ParamOptions`` to start from (copied); other arguments, when not None,
      override its fields.

    Returns a ``ParamResult``: converged, message, uv (k, 2) in [0, 1]^2, uv_triangles (m', 3)
    indices into uv per corner, vertices (n', 3) and triangles (m', 3) of the mesh parameterized
    (after edge splits; input vertices first), vertex_origin, cones, distortion (with
    flipped_faces), layout_error, lattice (flat torus: two complex numbers), seam_length, and
    the stages: flow, cut, cut_mesh, layout, atlas, cone_selection. When the flow does not
    converge, converged is False and message says why (nothing is raised).

    Raises ValueError for arrays of the wrong shape or dtype, TopologyError for non-manifold
    meshes, InvalidInput for bad cones or a mesh of several components.
    """
    mesh = _arrays.mesh(V, F)
    opts = _ricci.ParamOptions() if options is None else copy.copy(options)
    if isinstance(cones, str) and cones in _CONE_MODES:
        opts.cone_mode = cones
    elif isinstance(cones, _ricci.ConeMode):
        opts.cone_mode = cones
    elif isinstance(cones, (numbers.Integral, np.integer)) and not isinstance(cones, bool):
        if cones < 1:
            raise ValueError(f"cones: a cone count must be >= 1, got {cones}")
        opts.cone_mode = _ricci.ConeMode.Auto
        opts.auto_cones.count = int(cones)
    elif cones is not None:
        opts.cone_mode = _ricci.ConeMode.User
        opts.cones = cone_list(cones)
    set_fields(opts, boundary=boundary, quantize=quantize,
               modify_connectivity=modify_connectivity)
    set_fields(opts.auto_cones, max_log_scale=max_log_scale, max_cones=max_cones,
               try_first_cone_candidates=try_first_cone_candidates)
    set_structure_and_solver(opts, scheme=scheme, packing_init=packing_init,
                             max_intersection_angle=max_intersection_angle,
                             fit_sweeps=fit_sweeps, fit_tolerance=fit_tolerance, solver=solver,
                             tolerance=tolerance, max_iterations=max_iterations,
                             gradient_step=gradient_step, armijo=armijo,
                             max_backtracks=max_backtracks, use_cholmod=use_cholmod,
                             reuse_factorization_cg_iterations=reuse_factorization_cg_iterations,
                             progress=progress, flips=flips)
    return _ricci.parameterize(mesh, opts)
