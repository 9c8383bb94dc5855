"""ricci.sphere: the spherical conformal map of closed genus-0 meshes."""

import math

import numpy as np
import pytest

import ricci


def _check_sphere(V, F, result):
    """The invariants of docs/sphere.md, recomputed from the positions."""
    assert result.converged, result.message
    assert result.valid, result.message
    P = result.positions
    assert P.shape == np.asarray(V).shape
    assert np.abs(np.linalg.norm(P, axis=1) - 1).max() < 1e-12
    a, b, c = P[F[:, 0]], P[F[:, 1]], P[F[:, 2]]
    det = np.einsum("ij,ij->i", a, np.cross(b, c))
    assert (det > 0).all()
    assert result.inverted_faces == 0
    # Van Oosterom and Strackee: the signed areas sum to 4 pi for a single cover.
    area = 2 * np.arctan2(det, 1 + (a * b).sum(1) + (b * c).sum(1) + (c * a).sum(1))
    assert area.sum() == pytest.approx(4 * math.pi, abs=1e-8)
    # Centre of mass of the input's area carried onto the sphere.
    X = np.asarray(V, dtype=float)
    w = np.linalg.norm(np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]]), axis=1)
    n = a + b + c
    n /= np.linalg.norm(n, axis=1)[:, None]
    centre = (w[:, None] * n).sum(0) / w.sum()
    assert np.linalg.norm(centre) < 1e-9
    assert result.centre_of_mass < 1e-9


def test_icosphere(icosphere):
    V, F = icosphere
    result = ricci.sphere(V, F)
    _check_sphere(V, F, result)
    # Thurston: close to a rotation, not exactly one (measured 1.061 on 162 vertices).
    assert 1 <= result.angle_distortion_mean < 1.1
    assert result.flow.converged


def test_vertex_scaling_on_an_inscribed_mesh_is_a_rotation(icosphere):
    V, F = icosphere
    # Pole 0 is an icosahedron vertex: its link is a regular pentagon, which the disk-length
    # boundary reproduces exactly.
    result = ricci.sphere(V, F, scheme="vertex-scaling", pole=0)
    _check_sphere(V, F, result)
    # Inscribed mesh: the map is a rotation, so all inner products are kept.
    np.testing.assert_allclose(result.positions @ result.positions.T, V @ V.T, atol=1e-9)
    assert result.angle_distortion_max == pytest.approx(1, abs=1e-10)


def test_pole_and_options(icosphere):
    V, F = icosphere
    result = ricci.sphere(V, F, pole=7, scheme="inversive-distance", tolerance=1e-11)
    _check_sphere(V, F, result)
    assert result.pole == 7
    opts = ricci.SphereOptions(pole=3, centre_tolerance=1e-13)
    result = ricci.sphere(V, F, options=opts)
    assert result.pole == 3 and result.centre_of_mass <= 1e-13
    assert opts.pole == 3  # the caller's options are not changed
    assert "SphereResult(" in repr(result)


def test_precision_and_untangling_figures(icosphere):
    V, F = icosphere
    result = ricci.sphere(V, F, untangle=False)
    _check_sphere(V, F, result)
    # A round mesh: double resolves every face, nothing to untangle, nothing unresolved.
    assert result.precision_bits == 53
    assert 0 < result.min_plane_altitude < 1 and 0 < result.min_sphere_altitude < 1
    assert result.unresolved_faces == 0 and result.inverted_by_rounding == 0
    assert result.untangled_vertices == 0 and result.max_untangle_move == 0
    assert result.reversed_disk_faces == 0 and result.poles_tried == 1
    assert result.fixes == [] and result.message == ""
    assert math.isfinite(result.log_area_min) and result.log_area_min <= result.log_area_max
    assert ricci.SphereOptions(untangle=False).untangle is False


def test_progress_callback(icosphere):
    V, F = icosphere
    seen = []
    result = ricci.sphere(V, F, progress=lambda record: seen.append(record.max_error))
    assert result.converged and len(seen) == result.flow.components[0].flow.iterations + 1


def test_refusals(torus, icosphere):
    V, F = torus
    with pytest.raises(ricci.InvalidInput, match="genus 1"):
        ricci.sphere(V, F)
    V, F = ricci.generate.disk(4)
    with pytest.raises(ricci.InvalidInput, match="boundary loop"):
        ricci.sphere(V, F)
    V, F = icosphere
    with pytest.raises(ricci.InvalidInput, match="pole vertex 10000"):
        ricci.sphere(V, F, pole=10000)
    with pytest.raises(ValueError):
        ricci.sphere(V[:, :2], F)
