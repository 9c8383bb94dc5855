"""ricci.match and ricci.morph (issue 29): known answers on generated meshes."""

import numpy as np
import pytest

import ricci


def _lumpy_sphere():
    V, F = ricci.generate.icosphere(3)
    # No rotational symmetry (without the last term a half-turn about x would keep it).
    r = (1 + 0.15 * np.sin(3 * V[:, 0]) * np.cos(2 * V[:, 1]) + 0.1 * V[:, 2] ** 2
         + 0.1 * np.sin(2 * V[:, 1] + V[:, 2]))
    V = V * r[:, None] * np.array([1.4, 1.0, 0.8])
    return V, F


def test_a_moebius_copy_is_recovered_with_landmarks():
    VA, FA = _lumpy_sphere()
    # Inversion in a sphere about c, then a mirror: a Moebius transformation of space.
    c = np.array([3.0, 0.5, -0.4])
    d = VA - c
    VB = c + 6.25 * d / (d * d).sum(axis=1)[:, None]
    VB[:, 2] *= -1
    rng = np.random.default_rng(5)
    order = rng.permutation(len(VA))  # new index of old vertex v: order[v]
    VB_perm = np.empty_like(VB)
    VB_perm[order] = VB
    FB = order[FA]
    landmarks = np.array([[v, order[v]] for v in (0, 11, 100, 400)])
    m = ricci.match(VA, FA, VB_perm, FB, landmarks=landmarks, reverse=True)
    assert m.converged and m.domain == "sphere" and m.method == "landmarks"
    assert m.faces.shape == (len(VA),) and m.barycentric.shape == (len(VA), 3)
    np.testing.assert_allclose(m.barycentric.sum(axis=1), 1.0, atol=1e-12)
    diagonal = np.linalg.norm(VB.max(axis=0) - VB.min(axis=0))
    assert np.abs(m.positions - VB_perm[order]).max() / diagonal < 1e-6
    assert m.reverse_faces.shape == (len(VB),)


def test_a_rotated_copy_without_landmarks_and_its_morph():
    VA, FA = _lumpy_sphere()
    angle = 0.9
    R = np.array([[np.cos(angle), 0, np.sin(angle)], [0, 1, 0], [-np.sin(angle), 0, np.cos(angle)]])
    VB = VA @ R.T + np.array([2.0, 0.0, 1.0])
    m = ricci.match(VA, FA, VB, FA)
    assert m.method == "conformal factor"
    diagonal = np.linalg.norm(VB.max(axis=0) - VB.min(axis=0))
    assert np.abs(m.positions - VB).max() / diagonal < 1e-3
    frames = ricci.morph(VA, FA, VB, FA, frames=4)
    assert frames.shape == (4, len(VA), 3)
    # A rigid copy, moved back onto A: every frame is A.
    assert np.abs(frames - VA[None]).max() < 1e-3 * diagonal


def test_refuses_bad_landmarks_and_other_topologies():
    VA, FA = _lumpy_sphere()
    with pytest.raises(ValueError):
        ricci.match(VA, FA, VA, FA, landmarks=np.array([1.5, 2.5]))
    with pytest.raises(ricci.InvalidInput):
        ricci.match(VA, FA, VA, FA, landmarks=[[0, 10**6]])
    VT, FT = ricci.generate.torus(24, 8, 3.0, 1.0)
    with pytest.raises(ricci.InvalidInput):
        ricci.match(VA, FA, VT, FT)
