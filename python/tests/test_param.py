"""ricci.parameterize on a torus and on spheres with cones."""

import math

import numpy as np
import pytest

import ricci


def _check_uv(result):
    assert result.uv.ndim == 2 and result.uv.shape[1] == 2
    assert result.uv_triangles.shape == result.triangles.shape
    assert result.uv_triangles.min() >= 0 and result.uv_triangles.max() < len(result.uv)
    # The unit square, aspect ratio kept: one axis spans [0, 1] exactly.
    assert result.uv.min() >= -1e-12 and result.uv.max() <= 1 + 1e-12
    assert result.uv.max(axis=0).max() == pytest.approx(1, abs=1e-12)
    # Every face keeps its orientation in the plane.
    p = result.uv[result.uv_triangles]
    area = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    assert (area > 0).all()
    assert result.distortion.flipped_faces == 0
    assert result.layout_error < 1e-8


def test_torus_without_cones(torus):
    V, F = torus
    result = ricci.parameterize(V, F, cones="none")
    assert result.converged, result.message
    assert result.cones == []
    assert len(result.lattice) == 2
    assert all(isinstance(b, complex) for b in result.lattice)
    b1, b2 = result.lattice
    assert abs(b1) <= abs(b2) and abs((b1.conjugate() * b2).imag) > 0  # independent
    _check_uv(result)
    np.testing.assert_array_equal(result.vertices, V)  # no connectivity change on a torus
    np.testing.assert_array_equal(result.triangles, F)
    assert result.vertex_origin == list(range(len(V)))
    assert result.cut.num_generators == 2


def test_sphere_with_four_automatic_cones():
    V, F = ricci.generate.icosphere(3)
    result = ricci.parameterize(V, F, cones=4)
    assert result.converged, result.message
    assert len(result.cones) == 4
    assert sum(c.curvature for c in result.cones) == pytest.approx(4 * math.pi, abs=1e-9)
    assert result.lattice == []
    _check_uv(result)
    quantized = ricci.parameterize(V, F, cones=4, quantize=True)
    assert quantized.converged
    np.testing.assert_allclose([c.curvature for c in quantized.cones], math.pi, rtol=1e-15)
    _check_uv(quantized)


def test_sphere_with_user_cones(icosphere):
    V, F = icosphere
    result = ricci.parameterize(V, F, cones={v: math.pi / 3 for v in range(12)})
    assert result.converged, result.message
    assert sorted(c.vertex for c in result.cones) == list(range(12))
    _check_uv(result)


def test_disk_and_progress():
    V, F = ricci.generate.disk(8, 0.5)
    records = []
    result = ricci.parameterize(V, F, cones="none", boundary="disk", progress=records.append)
    assert result.converged
    assert records and records[-1].max_error <= 1e-12
    _check_uv(result)


def test_options_object_is_honoured(torus):
    V, F = torus
    options = ricci.ParamOptions(cone_mode="none", flow=ricci.FlowOptions(tolerance=1e-11))
    result = ricci.parameterize(V, F, options=options)
    assert result.converged and result.cones == []
    assert result.flow.max_error <= 1e-11
    assert len(result.lattice) == 2
