"""ricci.spline: manifold splines over the affine atlas (docs/splines.md)."""

import math

import numpy as np
import pytest

import ricci


def _bbox_diagonal(V):
    V = np.asarray(V)
    return float(np.linalg.norm(V.max(0) - V.min(0)))


def test_torus_is_c1_and_close_to_the_mesh():
    V, F = ricci.generate.torus(24, 12)
    s = ricci.spline(V, F)
    assert s.converged, s.message
    assert s.cones == []  # genus 1: the flat metric has no cones
    # C1 across every edge, cut edges included: jumps at rounding level.
    assert s.continuity.edges_checked == 3 * len(F) // 2
    assert s.continuity.relative_value_jump < 1e-9
    assert s.continuity.relative_gradient_jump < 1e-9
    # Close to the mesh (measured: distance max 6.2e-3, parametric max 6.3e-3 of the diagonal).
    assert 0 < s.error.max_distance < 0.01 and s.error.rms_distance <= s.error.max_distance
    assert 0 < s.error.max_parametric < 0.02
    assert s.error.bbox_diagonal == pytest.approx(_bbox_diagonal(V), rel=1e-12)
    # Surface: 6 pieces per face, refine^2 = 4 triangles each; control net: 4 per piece.
    SV, SF = s.surface
    assert SV.dtype == np.float64 and SV.shape[1] == 3
    assert SF.dtype == np.int32 and SF.shape == (24 * len(F), 3)
    assert SF.min() >= 0 and SF.max() == len(SV) - 1
    NV, NF = s.control_net
    assert NF.shape == (24 * len(F), 3) and NF.max() == len(NV) - 1
    # Closed surface: every edge of the surface mesh has two faces.
    edges = np.sort(np.concatenate([SF[:, [0, 1]], SF[:, [1, 2]], SF[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert (counts == 2).all()
    # Fitted values near the vertices, recomputed independently; gradients per vertex frame.
    assert s.values.shape == (len(V), 3) and s.gradients.shape == (len(V), 6)
    assert np.abs(s.values - V).max() / _bbox_diagonal(V) < 0.02
    np.testing.assert_array_equal(s.values, s.fit.values)
    # Surface points lie in their recorded domain faces.
    assert len(s.surface_faces) == len(SV)
    assert np.abs(s.surface_barycentric.sum(1) - 1).max() < 1e-12
    assert s.surface_barycentric.min() > -1e-12


def test_genus_two_has_cones_with_zero_gradient():
    V, F = ricci.generate.closed_surface(2, 10)
    s = ricci.spline(V, F, refine=1, smoothness=1e-3)
    assert s.converged, s.message
    assert len(s.cones) > 0
    assert s.continuity.relative_gradient_jump < 1e-9
    for cone in s.cones:
        assert np.abs(s.gradients[cone.vertex]).max() == 0
    assert s.surface[1].shape == (6 * len(s.param.triangles), 3)


def test_plane_is_reproduced_exactly():
    V, F = ricci.generate.disk(5, 0.0)
    a = np.array([[0.6, -0.8, 0], [0.8, 0.6, 0], [0.3, 0.5, 1]])  # rotation in xy, tilted
    V = V @ a.T + np.array([2.0, 0, 0])
    # Vertex scaling keeps the input's lengths, so the flat metric is the disk itself; Ptolemy
    # flips would change the metric.
    s = ricci.spline(V, F, scheme="vertex-scaling", flips="off")
    assert s.converged, s.message
    assert s.error.max_parametric < 1e-10
    assert 0 <= s.error.max_distance < 1e-10
    assert s.continuity.relative_value_jump < 1e-10
    assert s.continuity.relative_gradient_jump < 1e-10
    # Independently: every surface and control-net point in the disk's plane.
    normal = np.cross(V[F[0, 1]] - V[F[0, 0]], V[F[0, 2]] - V[F[0, 0]])
    normal /= np.linalg.norm(normal)
    diagonal = _bbox_diagonal(V)
    for points, _ in (s.surface, s.control_net):
        assert np.abs((points - V[0]) @ normal).max() / diagonal < 1e-10
    np.testing.assert_allclose(s.values, V, atol=1e-10 * diagonal)


def test_options_and_overrides():
    V, F = ricci.generate.torus(16, 8)
    opts = ricci.SplineOptions(refine=3, smoothness=1e-3)
    s = ricci.spline(V, F, options=opts, refine=1, measure_distance=False)
    assert s.converged
    assert s.surface[1].shape == (6 * len(F), 3)
    assert s.error.max_distance == -1  # not measured
    assert opts.refine == 3  # the caller's options are not changed
    # User cones on a torus: used as given (a cone pair summing to 0).
    s = ricci.spline(V, F, cones={0: "pi/2", 60: "-pi/2"}, refine=1)
    assert s.converged, s.message
    assert sorted(c.vertex for c in s.cones) == [0, 60]


@pytest.mark.parametrize("kwargs", [
    {"refine": 0}, {"refine": -2}, {"refine": 1.5}, {"refine": True},
    {"smoothness": 0}, {"smoothness": -1e-4}, {"smoothness": math.nan}, {"smoothness": math.inf},
    {"continuity_samples": 0}, {"cones": "0:x"}, {"scheme": "no-such-scheme"},
    {"options": ricci.ParamOptions()},
])
def test_bad_options_raise_invalid_input(kwargs):
    V, F = ricci.generate.torus(12, 6)
    with pytest.raises(ricci.InvalidInput):
        ricci.spline(V, F, **kwargs)


def test_bad_arrays_and_meshes():
    V, F = ricci.generate.torus(12, 6)
    with pytest.raises(ValueError):
        ricci.spline(V[:, :2], F)
    with pytest.raises(ValueError):
        ricci.spline(V, F, cones=0)
    # Two components: the parameterization takes one.
    V2 = np.vstack([V, V + 5])
    F2 = np.vstack([F, F + len(V)])
    with pytest.raises(ricci.InvalidInput):
        ricci.spline(V2, F2)
