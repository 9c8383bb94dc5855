"""ricci.flow(geometry='hyperbolic'): the uniformization metric of surfaces with chi < 0."""

import math

import numpy as np
import pytest

import ricci


def test_genus_two_uniformization_has_area_minus_two_pi_chi():
    V, F = ricci.generate.closed_surface(2, 8)
    result = ricci.flow(V, F, geometry="hyperbolic")
    assert result.converged and result.max_error <= 1e-10
    np.testing.assert_allclose(result.curvature, 0, atol=1e-10)
    flow = result.components[0].flow
    # Gauss-Bonnet in curvature -1: sum K - area = 2 pi chi = -4 pi.
    assert flow.total_area == pytest.approx(4 * math.pi, abs=1e-8)
    assert result.structure.structure.geometry == ricci.Geometry.Hyperbolic
    assert result.structure.structure.length_scale > 0


def test_boundary_is_geodesic_by_default():
    V, F = ricci.generate.surface_with_holes(0, 3, 10)  # a pair of pants, chi = -1
    result = ricci.flow(V, F, geometry="hyperbolic", scheme="vertex-scaling")
    assert result.converged
    np.testing.assert_allclose(result.curvature, 0, atol=1e-10)  # boundary included
    assert result.components[0].flow.total_area == pytest.approx(2 * math.pi, abs=1e-8)


def test_torus_and_virtual_radius_are_refused(torus):
    V, F = torus
    with pytest.raises(ricci.InvalidInput, match="chi"):
        ricci.flow(V, F, geometry="hyperbolic")
    V, F = ricci.generate.closed_surface(2, 6)
    with pytest.raises(ricci.InvalidInput, match="virtual-radius"):
        ricci.flow(V, F, geometry="hyperbolic", scheme="virtual-radius")
    with pytest.raises(ricci.InvalidInput, match="geometry"):
        ricci.flow(V, F, geometry="spherical")
