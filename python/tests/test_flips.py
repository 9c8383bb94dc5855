"""Intrinsic Delaunay edge flips from Python: the option, the counts and the flipped triangles."""

import math

import numpy as np
import pytest

import ricci

PI = math.pi
# A cone of angle 4 pi at a degree-5 vertex and four of curvature 1.5 pi: without flips vertex
# scaling breaks triangles around the big cone.
STRONG = {0: -2 * PI, 5: 1.5 * PI, 11: 1.5 * PI, 20: 1.5 * PI, 30: 1.5 * PI}


@pytest.fixture(scope="module")
def sphere():
    return ricci.generate.icosphere(3)


def test_flips_reach_what_the_input_triangulation_cannot(sphere):
    V, F = sphere
    off = ricci.flow(V, F, scheme="vertex-scaling", cones=STRONG, flips="off")
    assert not off.converged
    assert off.flips == 0
    # The library names the option field; Python phrases the fix as its own keyword.
    assert off.fixes == [("flips", "delaunay")]
    assert 'try: flips="delaunay"' in off.message
    assert "--flips" not in off.message
    on = ricci.flow(V, F, scheme="vertex-scaling", cones=STRONG)  # flips="auto"
    assert on.converged and on.max_error <= 1e-10
    assert on.flips > 0
    assert sum(r.flips for r in on.history[0]) == on.flips
    # Same vertices, the intrinsic triangulation: same face count, some faces changed.
    assert on.triangles.shape == F.shape
    assert not np.array_equal(on.triangles, F)
    assert on.edges.shape[0] == on.lengths.shape[0]
    assert on.components[0].flow.flips == on.flips


def test_flips_option_values(sphere):
    V, F = sphere
    with pytest.raises(ricci.InvalidInput, match="vertex-scaling"):
        ricci.flow(V, F, scheme="thurston", target="uniform", flips="delaunay")
    with pytest.raises(ricci.InvalidInput, match="flips"):
        ricci.flow(V, F, scheme="vertex-scaling", target="uniform", flips="sometimes")
    options = ricci.FlowOptions(flips="off")
    assert options.flips == ricci.EdgeFlips.Off


def test_parameterize_with_flips_keeps_the_input_faces(sphere):
    V, F = sphere
    result = ricci.parameterize(V, F, cones=STRONG, scheme="vertex-scaling",
                                modify_connectivity=False)
    assert result.converged, result.message
    assert result.flow.flips > 0
    np.testing.assert_array_equal(result.triangles, F)
    np.testing.assert_array_equal(result.vertices, V)
    assert result.distortion.flipped_faces == 0

def test_defaults_are_vertex_scaling_on_the_input_faces_with_the_natural_target():
    # A closed sphere with the default target (uniform there, flat needs cones) and the default
    # parameterization (cones where the topology needs them): every face of the input, no fold.
    V, F = ricci.generate.icosphere(3)
    flow = ricci.flow(V, F)
    assert flow.converged, flow.message
    assert "uniform" in flow.target.description
    assert flow.components[0].flow.error_floor > 0
    p = ricci.parameterize(V, F)
    assert p.converged, p.message
    np.testing.assert_array_equal(p.triangles, F)
    assert p.flow.structure.structure.scheme == ricci.Scheme.VertexScaling
    assert len(p.cones) >= 3 and p.routes[0].pipeline.cone_selection.within_bounds
    assert p.distortion.flipped_faces == 0
    assert p.timings.flow > 0 and p.routes[0].pipeline.development_length_mismatch < 1e-12


def test_a_tolerance_below_the_floor_ends_converged_at_the_floor(sphere):
    V, F = sphere
    r = ricci.flow(V, F, target="uniform", tolerance=1e-17)
    assert r.converged
    assert "floating-point floor" in r.components[0].flow.message
    assert r.max_error <= r.components[0].flow.error_floor
