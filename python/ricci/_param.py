"""Global conformal parameterization: ``parameterize`` wraps the C++ pipeline."""

import copy
import numbers

import numpy as np

from . import _arrays, _ricci
from ._flow import cone_list, set_fields, set_structure_and_solver

# The cone modes a string may name (the table in ricci/param/parameterize.hpp); "user" is
# spelled by giving the cones themselves.
_CONE_MODES = tuple(name for name in _ricci.ConeMode.names if name != "user")


def parameterize(V, F, *, cones=None, boundary=None, seams=None, quantize=None, max_log_scale=None,
                 max_cones=None, try_first_cone_candidates=None, cone_smoothness=None, modify_connectivity=None,
                 scheme=None, packing_init=None, max_intersection_angle=None, fit_sweeps=None,
                 fit_tolerance=None, solver=None, tolerance=None, max_iterations=None,
                 gradient_step=None, armijo=None, max_backtracks=None, use_cholmod=None,
                 reuse_factorization_cg_iterations=None, progress=None, flips=None,
                 geometry=None, root_face=None, gutter=None, polish=None, polygons=None,
                 untangle=None,
                 charts=None, options=None):
    """Global conformal parameterization of a manifold mesh: cones, valence raising, Ricci flow
    to a flat metric, cut graph, layout, atlas, distortion, uv in the unit square. A mesh of
    several components gets one atlas: each component is parameterized on its own (a component
    of one or two faces, or one whose flow fails, is unfolded in its own 3D shape; one whose
    unfolding needs several patches not to overlap counts as failed), its layout scaled
    to its 3D area, and the charts packed into the unit square without overlap.

    V: (n, 3) float positions; F: (m, 3) integer counter-clockwise triangles.

    cones: ``"needed"`` (the default: none where the topology allows, automatic on closed
      surfaces of genus 0 or >= 2), ``"auto"`` (automatic until max_log_scale holds), an int (that
      many automatic cones), ``"none"`` (a torus, or a surface with boundary), ``"one"`` (all
      of 2 pi chi at one vertex, genus >= 2), or user cones: ``[(vertex, curvature), ...]``,
      ``{vertex: curvature}`` or ``"V:K,V:K"`` (input vertex indices, radians or ``"pi/2"``).
    boundary: ``"free"`` (default), ``"disk"``, ``"disk-length"``.
    seams: ``"rigid"`` (default: the flat metric with cones, each seam's two copies related by a
      rigid motion) or ``"free"`` (the cones and cut as chosen, then the seams carry the curvature
      that distorts least; both copies of every seam edge keep one length, the rotation across a
      seam is free). routes[0].pipeline.seam_curvature says what the seams carry.
    quantize: round cone curvatures to multiples of pi/2.
    Automatic cones (``ConeSelectionOptions``): max_log_scale (1.0), max_cones (0: no cap),
      try_first_cone_candidates (1), cone_smoothness (1000: the curvatures minimise
      log(1 + E) + cone_smoothness D / #F, D the Dirichlet energy of the log scale; 0: area
      distortion E alone).
    modify_connectivity: split edges around cones whose valence is too low (True).
    Metric and solver: as ``ricci.flow`` (tolerance defaults to 1e-12 here), flips included:
      after Delaunay flips the triangles returned are the intrinsic Delaunay triangulation of
      the input vertices.
    geometry: ``"euclidean"`` (the default: a flat metric with cones, uv in the unit square)
      or ``"hyperbolic"`` (a surface with chi < 0: the uniformization metric laid out in the
      Poincare disk, see below).
    gutter: several components, the space between packed charts in uv units (0.002; options
      field packing.gutter).
    polish: after the layout, move the vertices on no seam and no boundary to lower the faces'
      mean angle distortion, seams, cones and boundary kept exact (True; options field
      polish.enabled). False: the discrete conformal map itself, every edge as long as the flat
      metric says. result.polish says what it did; its uv holds the positions before it.
    untangle: make the faces the exact map draws flipped positive, moving the vertices near
      them (seam vertices with all their copies), cones, seams and boundary kept exact (True;
      options field fold_free.untangle); result.untangle says what it did.
    charts: a component whose exact map still fails its checks (flipped faces, a layout that
      does not close up, a flow that fails, or automatic cones that cannot carry the curvature)
      is laid out as charts with free boundary: fold-free, every seam its 3D length (True;
      options field fold_free.charts). False: such a layout is returned as it is, with
      converged False. result.routes names the route of each component (ComponentRoute).
    polygons: a polygon mesh's faces over the triangles F (``info.polygons`` of
      ``read_mesh``): the cut never runs inside a face, and result.polygons gives the faces to
      write (``write_mesh(path, V, F, result.uv, result.uv_triangles,
      polygons=result.polygons)``), each listed from a corner whose fan is sound in the layout;
      result.distortion is measured on those fans.
    options: a ``ParamOptions`` (hyperbolic: ``HyperbolicParamOptions``) to start from
      (copied); other arguments, when not None, override its fields.

    Returns a ``MeshParamResult`` (the whole mesh's ``Parameterization``, with routes,
    components and packing): converged, message, uv (k, 2) in [0, 1]^2, uv_triangles (m', 3)
    indices into uv per corner, vertices (n', 3) and triangles (m', 3) of the mesh parameterized
    (after edge splits; input vertices first), vertex_origin, cones, distortion (with
    flipped_faces), layout_error, lattice (flat torus: two complex numbers), seam_length, and
    the stages: flow, cut, cut_mesh, layout, atlas. When the flow does not converge, converged
    is False and message says why (nothing is raised). routes names the route of each component,
    and routes[c].pipeline (``PipelineDiagnostics``) what its pipeline measured:
    cone_selection, log_scale_spread and cone_rounds (automatic cones),
    development_length_mismatch, seam_curvature, cone_refinement (a fixed count too few for
    the selection's bounds on a closed surface of chi < 0: two candidate cone sets measured on
    the flow, the better one's curvatures refined there). Several components (or one whose exact map gave way): the same
    fields cover the whole atlas, components lists a ``ComponentParam`` per component
    (method, parameterized, message, cones, distortion, overlapping_face_pairs, area_scale,
    chart, vertex_map, face_map, and param: the component's own ``ParamResult``), packing is the
    ``ChartPacking`` (coverage, scale, gutter, charts, overlapping_face_pairs), and converged is
    False when some component needed several patches (uv still covers every face).

    geometry="hyperbolic" (``parameterize_hyperbolic``): Ricci flow in the hyperbolic background
    to zero curvature at every vertex and geodesic boundary, cut graph, layout in the Poincare
    disk. It has no cones and no boundary choice: cones, boundary, quantize, the automatic-cone
    settings and modify_connectivity must be left out (``cones="none"`` and
    ``boundary="geodesic"`` are accepted), else InvalidInput. The metric and solver arguments
    apply as above; with scheme="vertex-scaling" the flow flips edges (hyperbolic intrinsic
    Delaunay flips, flips="auto"), and the input's own faces are developed in the final metric,
    so uv_triangles are always the input's faces. root_face picks the face laid out first (-1:
    the default). Returns a ``HyperbolicParamResult``: converged, message, uv (k, 2) with every
    |uv| < 1, uv_triangles (m, 3) per corner of the input's faces, segment_maps, node_words, has_group, group, distortion, seam_length, and the stages
    flow, cut, cut_mesh, layout (``HyperbolicLayout``: max_radius, max_length_relative_error,
    num_flipped_faces, segment_maps as ``SegmentIsometry``). Every Moebius map of the disk is a
    (2, 2) complex numpy matrix [[a, b], [conj b, conj a]] of determinant 1, acting by
    z -> (a z + b) / (conj(b) z + conj(a)); composing maps is the matrix product (M and -M are
    the same map). segment_maps[s] takes side B of cut segment s onto side A; node_words lists
    per cut-graph node the (segment, +1 or -1) crossed going around it, whose maps multiply to
    +-identity. On a closed surface (genus >= 2) group is a ``FuchsianGroup``: genus, a and b
    (lists of g matrices) with a1 b1 a1^-1 b1^-1 ... ag bg ag^-1 bg^-1 = +-identity, a_words and
    b_words (the generators as words in the segment maps), relation_residual, node_residual;
    with boundary group is None (has_group False). After flips development_length_mismatch
    says how well the developed input faces agree on their shared edges.

    Raises ValueError for arrays of the wrong shape or dtype, TopologyError for non-manifold
    meshes, InvalidInput for bad cones, and (hyperbolic) for
    a surface with chi >= 0 or a scheme without a hyperbolic energy (virtual-radius).
    """
    mesh = _arrays.mesh(V, F)
    for name, value in (("gutter", gutter), ("polish", polish), ("untangle", untangle),
                        ("charts", charts)):
        if value is not None and _is_hyperbolic(geometry):
            raise _ricci.InvalidInput(f"parameterize: {name} is an option of the Euclidean "
                                      "parameterization only")
    if _is_hyperbolic(geometry):
        return _parameterize_hyperbolic(
            mesh, cones=cones, boundary=boundary, quantize=quantize,
            max_log_scale=max_log_scale, max_cones=max_cones,
            try_first_cone_candidates=try_first_cone_candidates,
            cone_smoothness=cone_smoothness,
            modify_connectivity=modify_connectivity, scheme=scheme, packing_init=packing_init,
            max_intersection_angle=max_intersection_angle, fit_sweeps=fit_sweeps,
            fit_tolerance=fit_tolerance, solver=solver, tolerance=tolerance,
            max_iterations=max_iterations, gradient_step=gradient_step, armijo=armijo,
            max_backtracks=max_backtracks, use_cholmod=use_cholmod,
            reuse_factorization_cg_iterations=reuse_factorization_cg_iterations,
            progress=progress, flips=flips, root_face=root_face, polygons=polygons,
            options=options)
    if seams is not None and _is_hyperbolic(geometry):
        raise _ricci.InvalidInput("parameterize: seams is an option of the Euclidean "
                                  "parameterization only")
    if root_face is not None:
        raise _ricci.InvalidInput("parameterize: root_face is an option of "
                                  "geometry='hyperbolic' only")
    if options is not None and not isinstance(options, _ricci.ParamOptions):
        raise _ricci.InvalidInput(f"parameterize: options must be a ParamOptions for the "
                                  f"Euclidean parameterization, got {type(options).__name__}")
    opts = _ricci.ParamOptions() if options is None else copy.copy(options)
    set_cones(opts, cones)
    set_fields(opts, boundary=boundary, seams=seams, quantize=quantize,
               modify_connectivity=modify_connectivity, polygons=polygons)
    set_fields(opts.packing, gutter=gutter)
    set_fields(opts.polish, enabled=polish)
    set_fields(opts.fold_free, untangle=untangle, charts=charts)
    set_fields(opts.auto_cones, max_log_scale=max_log_scale, max_cones=max_cones,
               try_first_cone_candidates=try_first_cone_candidates, smoothness=cone_smoothness)
    set_structure_and_solver(opts, scheme=scheme, packing_init=packing_init,
                             max_intersection_angle=max_intersection_angle,
                             fit_sweeps=fit_sweeps, fit_tolerance=fit_tolerance, solver=solver,
                             tolerance=tolerance, max_iterations=max_iterations,
                             gradient_step=gradient_step, armijo=armijo,
                             max_backtracks=max_backtracks, use_cholmod=use_cholmod,
                             reuse_factorization_cg_iterations=reuse_factorization_cg_iterations,
                             progress=progress, flips=flips)
    return _ricci.parameterize(mesh, opts)


def set_cones(opts, cones):
    """Sets cone_mode (and cones or auto_cones.count) of a ParamOptions from the ``cones``
    argument of ``parameterize``; None keeps the options' own."""
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


def _is_hyperbolic(geometry):
    """Whether ``geometry`` (None, a name or a ``Geometry``) asks for the hyperbolic pipeline."""
    if geometry is None:
        return False
    if isinstance(geometry, str):
        geometry = _ricci.Geometry(geometry)  # unknown names raise InvalidInput
    if not isinstance(geometry, _ricci.Geometry):
        raise ValueError(f"geometry must be 'euclidean', 'hyperbolic' or a Geometry, "
                         f"got {geometry!r}")
    return geometry == _ricci.Geometry.Hyperbolic


def _parameterize_hyperbolic(mesh, *, cones, boundary, quantize, max_log_scale, max_cones,
                             try_first_cone_candidates, cone_smoothness, modify_connectivity,
                             root_face, polygons, options,
                             **structure_and_solver):
    """parameterize(geometry='hyperbolic'): refuses the Euclidean-only arguments, then calls
    ``parameterize_hyperbolic``."""
    if cones is not None and not (isinstance(cones, str) and cones == "none"):
        raise _ricci.InvalidInput(
            f"parameterize: cones={cones!r}: the hyperbolic parameterization has no cones (its "
            "metric has zero curvature at every vertex); leave cones out")
    if boundary is not None and boundary != "geodesic" and \
            boundary != _ricci.BoundaryMode.Geodesic:
        raise _ricci.InvalidInput(
            f"parameterize: boundary={boundary!r}: the hyperbolic parameterization gives every "
            "boundary zero geodesic curvature; leave boundary out")
    euclidean_only = {"quantize": quantize, "max_log_scale": max_log_scale,
                      "max_cones": max_cones,
                      "try_first_cone_candidates": try_first_cone_candidates,
                      "cone_smoothness": cone_smoothness,
                      "modify_connectivity": modify_connectivity}
    given = [name for name, value in euclidean_only.items() if value is not None]
    if given:
        raise _ricci.InvalidInput(
            f"parameterize: {', '.join(given)}: options of the Euclidean parameterization "
            "(cones and their placement), not of geometry='hyperbolic'")
    if options is None:
        opts = _ricci.HyperbolicParamOptions()
    elif isinstance(options, _ricci.HyperbolicParamOptions):
        opts = copy.copy(options)
    else:
        raise _ricci.InvalidInput(f"parameterize: options must be a HyperbolicParamOptions for "
                                  f"geometry='hyperbolic', got {type(options).__name__}")
    set_fields(opts.layout, root_face=root_face)
    set_fields(opts, polygons=polygons)
    set_structure_and_solver(opts, **structure_and_solver)
    return _ricci.parameterize_hyperbolic(mesh, opts)


def common_refinement(param, *, interpolation_matrix=None, options=None):
    """The exact discrete conformal map of a vertex-scaling parameterization, on the common
    refinement of the input triangulation, its intrinsic Delaunay triangulation and the final
    intrinsic triangulation (docs/parameterization.md, "The exact map").

    param: a converged result of ``parameterize(..., scheme="vertex-scaling")`` of one
    component, or a component's own ``ParamResult`` (``components[c].param``).
    interpolation_matrix: build the interpolation matrix (True).
    options: a ``CommonRefinementOptions`` to start from (copied).

    Returns a ``CommonRefinement``: vertices (r, 3) on the input surface (the input's vertices
    first, unchanged, then the crossing points), triangles (t, 3), and for every triangle the
    input_face, delaunay_face and intrinsic_face holding it; uv (k, 2) linear texture
    coordinates in param.uv's unit square (its rows first: the input vertices sit where the
    default output puts them) with uv_triangles (t, 3); projective_uv (3 t, 3): corner k of
    triangle t at row 3 t + k as (w u, w v, w), which interpolated linearly over the triangle and
    divided by w give the exact map; interpolation_triplets (rows, cols, values) of the (r, n)
    matrix of barycentric weights over the input's vertices (see
    ``interpolate_to_refinement``); delaunay_barycentric and intrinsic_barycentric (3 t, 3); and
    figures (flips undone, crossing points, max_intrinsic_length_error, seconds).
    Raises InvalidInput for another scheme or an unconverged result.
    """
    if not isinstance(param, _ricci.Parameterization):
        raise _ricci.InvalidInput(f"common_refinement: param must be a MeshParamResult or a "
                                  f"ParamResult, got "
                                  f"{type(param).__name__}")
    if options is not None and not isinstance(options, _ricci.CommonRefinementOptions):
        raise _ricci.InvalidInput(f"common_refinement: options must be a "
                                  f"CommonRefinementOptions, got {type(options).__name__}")
    opts = _ricci.CommonRefinementOptions() if options is None else copy.copy(options)
    set_fields(opts, interpolation_matrix=interpolation_matrix)
    return _ricci.common_refinement(param, opts)


def interpolate_to_refinement(refinement, values):
    """Carries per-vertex values of the mesh parameterized ((n,) or (n, k) array) onto the
    refinement's vertices with its interpolation matrix: (r,) or (r, k)."""
    rows, cols, weights = refinement.interpolation_triplets
    n = len(refinement.input_vertex)
    values = np.asarray(values, dtype=float)
    if values.ndim not in (1, 2) or values.shape[0] != n:
        raise ValueError(f"interpolate_to_refinement: expected ({n},) or ({n}, k) values, got "
                         f"shape {values.shape}")
    if len(rows) == 0 and n > 0:
        raise _ricci.InvalidInput("interpolate_to_refinement: the refinement was built without "
                                  "its interpolation matrix")
    out = np.zeros((refinement.vertices.shape[0],) + values.shape[1:])
    picked = values[cols]
    np.add.at(out, rows, picked * (weights[:, None] if values.ndim == 2 else weights))
    return out
