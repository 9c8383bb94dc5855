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


def _expect_refusals(run, torus, refusals):
    """run(V, F, geometry="hyperbolic") refuses the torus (chi = 0, no hyperbolic metric); on a
    genus-2 surface, run(V, F, **keywords) refuses each (match, keywords) of `refusals`, with a
    message matching `match` (None: any message)."""
    V, F = torus
    with pytest.raises(ricci.InvalidInput, match="chi"):
        run(V, F, geometry="hyperbolic")
    V, F = ricci.generate.closed_surface(2, 6)
    for match, keywords in refusals:
        with pytest.raises(ricci.InvalidInput, match=match):
            run(V, F, **keywords)


def test_torus_and_virtual_radius_are_refused(torus):
    _expect_refusals(ricci.flow, torus, [
        ("virtual-radius", dict(geometry="hyperbolic", scheme="virtual-radius")),
        ("geometry", dict(geometry="spherical")),
    ])


# ricci.parameterize(geometry='hyperbolic'): the uniformization metric in the Poincare disk.

@pytest.fixture(scope="module")
def genus_two_param():
    V, F = ricci.generate.closed_surface(2, 10)
    return V, F, ricci.parameterize(V, F, geometry="hyperbolic")


def test_genus_two_lies_in_the_disk(genus_two_param):
    V, F, result = genus_two_param
    assert isinstance(result, ricci.HyperbolicParamResult)
    assert result.converged, result.message
    assert result.uv.shape[1] == 2 and result.uv.shape[0] >= len(V)
    assert np.all(np.hypot(result.uv[:, 0], result.uv[:, 1]) < 1)
    assert result.uv_triangles.shape == (len(F), 3)
    assert result.uv_triangles.min() >= 0 and result.uv_triangles.max() < len(result.uv)
    layout = result.layout
    assert layout.max_radius < 1 and layout.num_flipped_faces == 0
    assert layout.max_length_relative_error < 1e-8
    assert result.distortion.flipped_faces == 0
    assert result.flow.components[0].flow.total_area == pytest.approx(4 * math.pi, abs=1e-8)
    # One map and two crossings (once per end) per cut segment.
    assert len(result.segment_maps) == len(result.cut.segments) == len(layout.segment_maps)
    crossings = [s for word in result.node_words for s, sign in word]
    assert sorted(crossings) == sorted(2 * list(range(len(result.segment_maps))))


def _det(M):
    return M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0]


def _distance_to_identity(M):
    I = np.eye(2)
    return min(np.abs(M - I).max(), np.abs(M + I).max())


def test_genus_two_fuchsian_group(genus_two_param):
    _, _, result = genus_two_param
    assert result.has_group
    group = result.group
    assert group.genus == 2 and len(group.a) == 2 and len(group.b) == 2
    assert len(group.a_words) == 2 and len(group.b_words) == 2
    assert group.relation_residual < 1e-8 and group.node_residual < 1e-8
    for M in group.a + group.b:
        assert M.shape == (2, 2) and M.dtype == np.complex128
        assert abs(_det(M) - 1) < 1e-12
        # SU(1,1) shape: [[a, b], [conj b, conj a]].
        assert M[1, 0] == np.conj(M[0, 1]) and M[1, 1] == np.conj(M[0, 0])
    # The relation recomputed here: a1 b1 a1^-1 b1^-1 a2 b2 a2^-1 b2^-1 = +-I.
    product = np.eye(2, dtype=complex)
    for a, b in zip(group.a, group.b):
        product = product @ a @ b @ np.linalg.inv(a) @ np.linalg.inv(b)
    assert _distance_to_identity(product) < 1e-8
    # Each generator is its word in the segment maps.
    maps = result.segment_maps
    for word, M in zip(group.a_words + group.b_words, group.a + group.b):
        W = np.eye(2, dtype=complex)
        for segment, sign in word:
            W = W @ (maps[segment] if sign > 0 else np.linalg.inv(maps[segment]))
        assert _distance_to_identity(W @ np.linalg.inv(M)) < 1e-8


def test_pair_of_pants_has_no_group():
    V, F = ricci.generate.surface_with_holes(0, 3, 10)
    result = ricci.parameterize(V, F, geometry=ricci.Geometry.Hyperbolic,
                                scheme="vertex-scaling")
    assert result.converged, result.message
    assert not result.has_group and result.group is None
    assert np.all(np.hypot(result.uv[:, 0], result.uv[:, 1]) < 1)
    assert result.flow.components[0].flow.total_area == pytest.approx(2 * math.pi, abs=1e-8)


def test_hyperbolic_parameterize_refuses(torus):
    _expect_refusals(ricci.parameterize, torus, [
        ("cones", dict(geometry="hyperbolic", cones=3)),
        ("boundary", dict(geometry="hyperbolic", boundary="disk")),
        ("quantize", dict(geometry="hyperbolic", quantize=True)),
        ("virtual-radius", dict(geometry="hyperbolic", scheme="virtual-radius")),
        ("HyperbolicParamOptions", dict(geometry="hyperbolic", options=ricci.ParamOptions())),
        (None, dict(geometry="spherical")),
    ])


def test_hyperbolic_options_are_passed_on():
    V, F = ricci.generate.closed_surface(2, 6)
    opts = ricci.HyperbolicParamOptions()
    opts.flow.tolerance = 1e-11
    result = ricci.parameterize(V, F, geometry="hyperbolic", options=opts, root_face=0)
    assert result.converged and result.flow.max_error <= 1e-11
    assert result.layout.root_face == 0
    assert opts.layout.root_face == -1  # the options given were copied


def test_parameterize_reports_the_refinement_and_the_cut_search():
    V, F = ricci.generate.closed_surface(4, 8)
    result = ricci.parameterize(V, F, geometry="hyperbolic")
    assert result.converged
    assert result.refined_error < 1e-16  # the long double refinement of the metric
    assert 1 <= result.cut_candidates_tried <= 32
    assert result.group.genus == 4 and result.group.relation_residual < 1e-8
    # One cut only: the first candidate, the default root.
    one = ricci.parameterize(V, F, geometry="hyperbolic",
                             options=ricci.HyperbolicParamOptions(cut_candidates=1))
    assert one.cut_candidates_tried == 1 and one.cut_root == -1


# Hyperbolic intrinsic Delaunay flips (vertex scaling): what the input triangulation cannot reach.

def _spiky(V, F, stride=5, push=1.0):
    """Every stride-th face split 1-to-3 near its first corner, the new vertex pushed out along
    the face normal by push times the face's longest edge: valence-3 spikes."""
    V = [np.asarray(v, dtype=float) for v in V]
    faces = []
    for f, (a, b, c) in enumerate(F):
        if f % stride:
            faces.append((a, b, c))
            continue
        pa, pb, pc = V[a], V[b], V[c]
        normal = np.cross(pb - pa, pc - pa)
        normal /= np.linalg.norm(normal)
        longest = max(np.linalg.norm(pb - pa), np.linalg.norm(pc - pb), np.linalg.norm(pa - pc))
        V.append(0.8 * pa + 0.1 * pb + 0.1 * pc + push * longest * normal)
        p = len(V) - 1
        faces += [(a, b, p), (b, c, p), (c, a, p)]
    return np.array(V), np.array(faces, dtype=np.int32)


@pytest.fixture(scope="module")
def spiky_genus_two():
    return _spiky(*ricci.generate.closed_surface(2, 12))


def test_hyperbolic_flips_uniformize_spikes(spiky_genus_two):
    V, F = spiky_genus_two
    off = ricci.flow(V, F, geometry="hyperbolic", scheme="vertex-scaling", flips="off")
    assert not off.converged and off.flips == 0
    on = ricci.flow(V, F, geometry="hyperbolic", scheme="vertex-scaling")  # flips="auto"
    assert on.converged and on.max_error <= 1e-10, on.message
    flow = on.components[0].flow
    assert on.flips > flow.isometric_flips > 0  # isometric first, then Ptolemy
    assert flow.total_area == pytest.approx(4 * math.pi, abs=1e-8)
    assert on.eta.shape == on.lengths.shape and on.triangles.shape == F.shape
    assert not np.array_equal(on.triangles, F)


def test_hyperbolic_parameterize_with_flips_keeps_the_input_faces(spiky_genus_two):
    V, F = spiky_genus_two
    result = ricci.parameterize(V, F, geometry="hyperbolic", scheme="vertex-scaling")
    assert result.converged, result.message
    assert result.flow.flips > 0
    # uv per corner of the input's faces: each cut-mesh corner copies the input's vertex.
    to_original = np.asarray(result.cut_mesh.to_original)
    np.testing.assert_array_equal(to_original[result.uv_triangles], F)
    assert np.all(np.hypot(result.uv[:, 0], result.uv[:, 1]) < 1)
    assert result.group.genus == 2 and result.group.relation_residual < 1e-10
    assert result.development_length_mismatch < 1e-14
    assert result.refined_error < 1e-16
