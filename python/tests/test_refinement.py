"""ricci.common_refinement: the exact map of a vertex-scaling parameterization on the common
refinement, checked from the arrays alone."""

import math

import numpy as np
import pytest

import ricci


def _valence3_sphere():
    """An icosphere whose faces are split 1-to-3 near a corner: needles and valence-3 vertices,
    whose intrinsic Delaunay triangulation is many flips away."""
    V, F = ricci.generate.icosphere(1)
    n = len(V)
    w = 0.05
    new = 1.01 * ((1 - 2 * w) * V[F[:, 0]] + w * (V[F[:, 1]] + V[F[:, 2]]))
    c = n + np.arange(len(F))
    F2 = np.concatenate([np.stack([F[:, 0], F[:, 1], c], 1), np.stack([F[:, 1], F[:, 2], c], 1),
                         np.stack([F[:, 2], F[:, 0], c], 1)])
    return np.concatenate([V, new]), F2


@pytest.fixture(scope="module")
def exact():
    V, F = _valence3_sphere()
    param = ricci.parameterize(V, F, scheme="vertex-scaling",
                               cones={0: 1.5 * math.pi, 5: 1.5 * math.pi, 20: math.pi})
    assert param.converged, param.message
    return V, F, param, ricci.common_refinement(param)


def test_sizes_and_flips(exact):
    V, F, param, r = exact
    assert r.isometric_flips > 50 and r.ptolemy_flips > 5
    assert len(r.vertices) == len(V) + r.input_delaunay_points + r.delaunay_intrinsic_points + \
        r.interior_points
    assert len(r.triangles) > len(F)
    assert r.inverted_triangles == 0


def test_input_vertices_where_the_flat_metric_puts_them(exact):
    V, F, param, r = exact
    np.testing.assert_array_equal(r.vertices[:len(V)], V)
    # The default output is polished (interior vertices moved to lower the angle distortion);
    # the refinement, the exact map, puts the input's vertices where the layout had them before.
    assert param.polish.moved_vertices > 0
    exact_uv = (param.polish.uv - param.uv_offset) * param.uv_scale
    np.testing.assert_array_equal(r.uv[:len(param.uv)], exact_uv)
    V2, F2 = _valence3_sphere()
    # (Untangling would move the vertices of the faces drawn flipped too, and the charts route
    # would replace a layout with flipped faces.)
    unpolished = ricci.parameterize(V2, F2, scheme="vertex-scaling", polish=False, untangle=False,
                                    charts=False,
                                    cones={0: 1.5 * math.pi, 5: 1.5 * math.pi, 20: math.pi})
    assert unpolished.polish.moved_vertices == 0
    np.testing.assert_array_equal(r.uv[:len(param.uv)], unpolished.uv)
    np.testing.assert_array_equal(ricci.common_refinement(unpolished).uv, r.uv)
    assert r.input_vertex == list(range(len(V)))
    assert r.max_corner_mismatch < 1e-9


def test_projective_coordinates(exact):
    V, F, param, r = exact
    t = len(r.triangles)
    assert r.projective_uv.shape == (3 * t, 3)
    w = r.projective_uv[:, 2]
    assert (w > 0).all() and (w <= 1).all()
    np.testing.assert_allclose(w.reshape(t, 3).max(axis=1), 1)
    corners = r.uv[r.uv_triangles].reshape(3 * t, 2)
    np.testing.assert_allclose(r.projective_uv[:, :2] / w[:, None], corners, atol=1e-12)
    assert r.max_intrinsic_length_error < 1e-9


def test_interpolation_matrix_reproduces_positions_and_fills_faces(exact):
    V, F, param, r = exact
    rows, cols, values = r.interpolation_triplets
    sums = np.zeros(len(r.vertices))
    np.add.at(sums, rows, values)
    np.testing.assert_allclose(sums, 1, atol=1e-14)
    np.testing.assert_allclose(ricci.interpolate_to_refinement(r, V), r.vertices, atol=1e-13)
    # The pieces of each input face add up to its area.
    p = r.vertices[r.triangles]
    piece_area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    total = np.zeros(len(F))
    np.add.at(total, np.asarray(r.input_face), piece_area)
    q = V[F]
    face_area = 0.5 * np.linalg.norm(np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]), axis=1)
    np.testing.assert_allclose(total, face_area, rtol=1e-12)
    with pytest.raises(ValueError):
        ricci.interpolate_to_refinement(r, V[:-1])


def test_other_schemes_are_refused(torus):
    V, F = torus
    param = ricci.parameterize(V, F, cones="none", scheme="thurston")
    assert param.converged
    with pytest.raises(ricci.InvalidInput):
        ricci.common_refinement(param)
    with pytest.raises(ricci.InvalidInput):
        ricci.common_refinement("not a result")
