"""Manifold splines: ``spline`` wraps ``fit_manifold_spline`` (ricci/spline/manifold_spline.hpp)."""

import copy
import math
import numbers

import numpy as np

from . import _arrays, _ricci
from ._flow import set_fields, set_structure_and_solver
from ._param import set_cones


def spline(V, F, *, smoothness=None, refine=None, cones=None, boundary=None, quantize=None,
           scheme=None, flips=None, tolerance=None, max_iterations=None, measure_distance=None,
           continuity_samples=None, progress=None, options=None):
    """Manifold spline of a single-component manifold mesh (docs/splines.md): the mesh is
    parameterized over a flat metric with cones, a C1 quadratic Powell-Sabin spline over the
    affine atlas is fitted to its positions, then evaluated as a triangle mesh, with its control
    net, its fitting error and a check of its continuity across every edge.

    V: (n, 3) float positions; F: (m, 3) integer counter-clockwise triangles.

    smoothness: dimensionless weight of the smoothness term (1e-4; > 0): larger is smoother and
      further from the data.
    refine: each quadratic piece split refine x refine in the surface (2; >= 1).
    cones: None (the default) picks by topology: no cones for surfaces with boundary and for
      genus 1, automatic cones otherwise; any other value as ``parameterize`` (``"auto"``,
      a count, ``"none"``, ``"one"``, or user cones) and used as given.
    boundary, quantize, scheme, flips, tolerance (1e-12), max_iterations, progress: the
      parameterization, as ``parameterize``. The planar case is reproduced exactly with
      ``scheme="vertex-scaling", flips="off"`` (the flat metric is then the plane itself).
    measure_distance: measure the distance to the input surface (True); continuity_samples:
      points per interior edge of the C1 check (5).
    options: a ``SplineOptions`` to start from (copied); other arguments override its fields.

    Returns a ``SplineResult``: converged, message, surface and control_net (each a (V, F)
    tuple of float64 (k, 3) and int32 (l, 3) arrays), values (n', 3) and gradients (n', 6) at
    the domain's vertices (gradients in each vertex's frame), cones (``Cone`` list), error
    (``SplineError``: max / rms parametric and distance errors relative to the bounding-box
    diagonal), continuity (``ContinuityReport``: relative_value_jump, relative_gradient_jump),
    fit (``SplineFit``), param (the ``MeshParamResult`` of the domain: its vertices and triangles
    index values and gradients), surface_faces and surface_barycentric (where each surface
    point lies in the domain) and timings. When the parameterization does not converge,
    converged is False and message says why (nothing is raised).

    Raises ValueError for arrays of the wrong shape or dtype, InvalidInput for bad options
    (refine < 1, smoothness <= 0, bad cones) or a mesh of several components, TopologyError for
    non-manifold meshes.
    """
    mesh = _arrays.mesh(V, F)
    if options is not None and not isinstance(options, _ricci.SplineOptions):
        raise _ricci.InvalidInput(f"spline: options must be a SplineOptions, got "
                                  f"{type(options).__name__}")
    opts = _ricci.SplineOptions() if options is None else copy.copy(options)
    if refine is not None:
        if isinstance(refine, bool) or not isinstance(refine, (numbers.Integral, np.integer)) \
                or refine < 1:
            raise _ricci.InvalidInput(f"spline: refine must be an integer >= 1, got {refine!r}")
        opts.refine = int(refine)
    if smoothness is not None:
        if isinstance(smoothness, bool) or not isinstance(smoothness, numbers.Real) \
                or not math.isfinite(smoothness) or smoothness <= 0:
            raise _ricci.InvalidInput(f"spline: smoothness must be a finite number > 0, got "
                                      f"{smoothness!r}")
        opts.smoothness = float(smoothness)
    if continuity_samples is not None and continuity_samples < 1:
        raise _ricci.InvalidInput(f"spline: continuity_samples must be >= 1, got "
                                  f"{continuity_samples!r}")
    set_fields(opts, measure_distance=measure_distance, continuity_samples=continuity_samples)
    param = opts.param  # a view into opts
    if cones is not None:
        opts.choose_cone_mode = False
        set_cones(param, cones)
    set_fields(param, boundary=boundary, quantize=quantize)
    set_structure_and_solver(param, scheme=scheme, packing_init=None, max_intersection_angle=None,
                             fit_sweeps=None, fit_tolerance=None, solver=None,
                             tolerance=tolerance, max_iterations=max_iterations,
                             gradient_step=None, armijo=None, max_backtracks=None,
                             use_cholmod=None, reuse_factorization_cg_iterations=None,
                             progress=progress, flips=flips)
    return _ricci.fit_manifold_spline(mesh, opts)
