"""The Ricci flow on a whole mesh: ``flow`` wraps the C++ ``flow_mesh``."""

import copy
import numbers

from . import _arrays, _ricci

# Boundary modes a target string may name (the table in ricci/flow/target.hpp).
_BOUNDARY_TARGETS = _ricci.BoundaryMode.names


def set_fields(obj, **fields):
    """Assigns every field whose value is not None (None keeps the options' own value)."""
    for name, value in fields.items():
        if value is not None:
            setattr(obj, name, value)


def cone_list(cones):
    """Cones as a list of ``Cone``. Accepts a list of ``(vertex, curvature)`` pairs or ``Cone``
    objects, a dict ``{vertex: curvature}``, or the command line's text ``"V:K,V:K"``.
    Curvatures are radians, or text such as ``"pi/2"``."""
    if isinstance(cones, str):
        return _ricci.parse_cone_list(cones)
    items = cones.items() if isinstance(cones, dict) else cones
    out = []
    for item in items:
        if isinstance(item, _ricci.Cone):
            out.append(_ricci.Cone(item.vertex, item.curvature))
            continue
        try:
            vertex, curvature = item
        except (TypeError, ValueError):
            raise ValueError(f"a cone must be a (vertex, curvature) pair, got {item!r}") from None
        if isinstance(vertex, bool) or not isinstance(vertex, numbers.Real) or \
                int(vertex) != vertex:
            raise ValueError(f"a cone vertex must be an integer, got {vertex!r}")
        if isinstance(curvature, str):
            curvature = _ricci.parse_curvature(curvature)
        out.append(_ricci.Cone(int(vertex), float(curvature)))
    return out


def flow(V, F, *, target=None, cones=None, boundary=None, scheme=None, geometry=None,
         packing_init=None,
         max_intersection_angle=None, fit_sweeps=None, fit_tolerance=None, solver=None,
         tolerance=None, max_iterations=None, gradient_step=None, armijo=None,
         max_backtracks=None, use_cholmod=None, reuse_factorization_cg_iterations=None,
         progress=None, flips=None, vertex_labels=None, options=None):
    """Runs the discrete Ricci flow on every connected component of a mesh (``flow_mesh``).

    V: (n, 3) float positions; F: (m, 3) integer counter-clockwise triangles.

    Target (``TargetSpec``):
      target: ``"natural"`` (the default: per component, flat where its topology admits a flat
        metric, i.e. with boundary or a torus, uniform curvature otherwise; flat with cones;
        zero curvature in the hyperbolic geometry), ``"flat"`` (zero curvature but at the
        cones), ``"free"``, ``"disk"`` or ``"disk-length"`` (flat with that boundary mode),
        ``"uniform"`` (2 pi chi / n per vertex), or an (n,) array of per-vertex target
        curvatures.
      cones: natural or flat target: ``[(vertex, curvature), ...]``, ``{vertex: curvature}`` or
        ``"V:K,V:K"``; curvature in radians or text like ``"pi/2"``.
      boundary: ``"free"`` (u fixed on the boundary, the Euclidean default), ``"disk"``,
        ``"disk-length"``, ``"geodesic"`` (zero boundary curvature, the hyperbolic default).
    Metric (``StructureOptions``): scheme (``"vertex-scaling"``, the default: discrete conformal
      equivalence with intrinsic Delaunay flips, ``"thurston"``, the tutorial's circle packing,
      ``"tangential"``, ``"inversive-distance"``, ``"virtual-radius"``), geometry
      (``"euclidean"``, the default, or ``"hyperbolic"``: curvature -1, where the flat target
      gives the uniformization metric of a surface with chi < 0; the result's components then
      report ``total_area``; virtual-radius has no hyperbolic energy), packing_init
      (``"fit"`` or ``"unit"``), max_intersection_angle (radians), fit_sweeps, fit_tolerance.
    Solver (``FlowOptions``): solver (``"newton"``, the default, or ``"gradient"``), tolerance
      (1e-10 radians), max_iterations (0: 200 Newton, 1e6 gradient), gradient_step, armijo,
      max_backtracks, use_cholmod, reuse_factorization_cg_iterations, and progress: a callable
      taking an ``IterationRecord`` after every iteration; returning False stops the flow
      (status ``FlowStatus.Cancelled``). flips: ``"auto"`` (the default: intrinsic Delaunay edge
      flips for vertex scaling, in either geometry, which then reaches every target that
      satisfies Gauss-Bonnet), ``"off"`` or ``"delaunay"``; after flips ``triangles``, ``edges``
      and ``eta`` describe the intrinsic triangulation of the same vertices.
    vertex_labels: numbers error messages show for vertices.
    options: a ``MeshFlowOptions`` to start from (copied); the other arguments, when not None,
      override its fields. None everywhere means the C++ default.

    Returns a ``MeshFlowResult``: converged, status, message, max_error, u, curvature,
    target_curvature (n,), edges (E, 2), lengths (E,), triangles (m, 3), flips, history (per component, a list of
    IterationRecord), timings (per component), fit_error, components, structure, target,
    topology. Non-convergence is reported there, not raised.

    Raises ValueError for arrays of the wrong shape or dtype, TopologyError for non-manifold
    meshes, InvalidInput (a ValueError) for an inadmissible target (e.g. cones breaking
    Gauss-Bonnet), SolverError when the linear algebra breaks down.
    """
    mesh = _arrays.mesh(V, F)
    opts = _ricci.MeshFlowOptions() if options is None else copy.copy(options)
    spec = opts.target
    if isinstance(target, str):
        if target in _BOUNDARY_TARGETS:
            if boundary is not None and boundary != target:
                raise ValueError(f"target {target!r} and boundary {boundary!r} disagree")
            spec.kind, boundary = _ricci.TargetKind.Flat, target
        else:
            spec.kind = target  # "flat", "uniform", "values"; others raise InvalidInput
    elif isinstance(target, _ricci.TargetKind):
        spec.kind = target
    elif target is not None:
        spec.kind = _ricci.TargetKind.Values
        spec.values = _arrays.per_vertex(target, mesh.num_vertices, "target")
    if spec.kind == _ricci.TargetKind.Values and spec.values.shape[0] != mesh.num_vertices:
        raise ValueError(f"target 'values' needs an ({mesh.num_vertices},) array of curvatures")
    if cones is not None:
        spec.cones = cone_list(cones)
    if spec.cones and spec.kind not in (_ricci.TargetKind.Flat, _ricci.TargetKind.Natural):
        raise ValueError("cones need a flat target (target='flat', 'free', 'disk' or "
                         "'disk-length')")
    if geometry is not None:
        opts.structure.geometry = geometry
    if boundary is None and opts.structure.geometry == _ricci.Geometry.Hyperbolic:
        boundary = "geodesic"
    set_fields(spec, boundary=boundary)
    set_structure_and_solver(opts, scheme=scheme, packing_init=packing_init,
                             max_intersection_angle=max_intersection_angle,
                             fit_sweeps=fit_sweeps, fit_tolerance=fit_tolerance, solver=solver,
                             tolerance=tolerance, max_iterations=max_iterations,
                             gradient_step=gradient_step, armijo=armijo,
                             max_backtracks=max_backtracks, use_cholmod=use_cholmod,
                             reuse_factorization_cg_iterations=reuse_factorization_cg_iterations,
                             progress=progress, flips=flips)
    if vertex_labels is not None:
        opts.vertex_labels = [int(v) for v in vertex_labels]
    return _ricci.flow_mesh(mesh, opts)


def set_structure_and_solver(opts, *, scheme, packing_init, max_intersection_angle, fit_sweeps,
                             fit_tolerance, solver, tolerance, max_iterations, gradient_step,
                             armijo, max_backtracks, use_cholmod,
                             reuse_factorization_cg_iterations, progress, flips=None):
    """Sets the StructureOptions and FlowOptions fields shared by flow() and parameterize() on
    an options object with .structure and .flow; None keeps a field's default."""
    set_fields(opts.structure, scheme=scheme, packing_init=packing_init,
               max_intersection_angle=max_intersection_angle, fit_sweeps=fit_sweeps,
               fit_tolerance=fit_tolerance)
    set_fields(opts.flow, solver=solver, tolerance=tolerance, max_iterations=max_iterations,
               gradient_step=gradient_step, armijo=armijo, max_backtracks=max_backtracks,
               use_cholmod=use_cholmod,
               reuse_factorization_cg_iterations=reuse_factorization_cg_iterations,
               progress=progress, flips=flips)
