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


def _side_by_side(*parts):
    """Meshes (V, F, scale) as one mesh of several components, moved apart along x."""
    Vs, Fs, x, n = [], [], 0.0, 0
    for V, F, s in parts:
        V = np.asarray(V, float) * s
        V = V + [x - V[:, 0].min(), 0, 0]
        x = V[:, 0].max() + s
        Vs.append(V)
        Fs.append(np.asarray(F) + n)
        n += len(V)
    return np.vstack(Vs), np.vstack(Fs)


def test_several_components_share_one_atlas(torus):
    triangle = ([[0, 0, 0], [1, 0, 0], [0.2, 0.9, 0]], [[0, 1, 2]], 10.0)
    V, F = _side_by_side((*torus, 1.0), (*ricci.generate.icosphere(3), 100.0),
                         (*ricci.generate.tetrahedron(), 0.1), triangle)
    result = ricci.parameterize(V, F, scheme="vertex-scaling", gutter=0.01)
    assert result.converged, result.message
    methods = [c.method for c in result.components]
    # The tetrahedron goes by the flow (three cones); the lone triangle is unfolded.
    assert methods == [ricci.ComponentMethod.Flow, ricci.ComponentMethod.Flow,
                       ricci.ComponentMethod.Flow, ricci.ComponentMethod.Unfolded]
    assert [len(c.faces) for c in result.components] == [len(torus[1]), 1280, 4, 1]
    packing = result.packing
    assert packing.gutter == 0.01 and len(packing.charts) == 4
    assert packing.overlapping_face_pairs == 0
    assert ricci.find_uv_overlaps(result.uv, result.uv_triangles, packing.face_chart).count == 0
    assert result.uv.min() >= 0.005 - 1e-12 and result.uv.max() <= 0.995 + 1e-12
    # One texel density: uv area / 3D area is the same for every component.
    p = result.uv[result.uv_triangles]
    uv_area = 0.5 * np.abs(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]))
    q = result.vertices[result.triangles]
    area = 0.5 * np.linalg.norm(np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]), axis=1)
    density = [uv_area[c.face_map].sum() / area[c.face_map].sum() for c in result.components]
    assert density == pytest.approx([result.uv_scale ** 2] * 4, rel=1e-9)
    assert packing.coverage == pytest.approx(uv_area.sum(), rel=1e-12)
    # Each component's own result, and its cones in whole-mesh indices.
    sphere = result.components[1]
    assert sphere.param.converged and len(sphere.cones) == len(sphere.param.cones) > 0
    assert all(c.vertex == sphere.vertex_map[d.vertex]
               for c, d in zip(sphere.cones, sphere.param.cones))
    assert all(c.parameterized and c.message == "" for c in result.components)
    # With no cones asked for, the tetrahedron cannot flatten: unfolded, four cones of pi.
    result = ricci.parameterize(V, F, scheme="vertex-scaling", cones="none")
    tetrahedron = result.components[2]
    assert result.converged and tetrahedron.method == ricci.ComponentMethod.Unfolded
    assert "no flat metric without cones" in tetrahedron.message
    assert [c.curvature for c in tetrahedron.cones] == pytest.approx([math.pi] * 4, abs=1e-12)


def test_pack_charts_and_overlaps():
    # Two unit squares (two triangles each) and a triangle, overlapping where they are given.
    layout = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5], [1.5, 0.5], [1.5, 1.5],
                       [0.5, 1.5], [0, 0], [2, 0], [0, 2]], float)
    faces = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7], [8, 9, 10]])
    assert ricci.find_uv_overlaps(layout, faces).count > 0
    packed = ricci.pack_charts(layout, faces, options=ricci.ChartPackingOptions(gutter=0.05))
    assert len(packed.charts) == 3 and list(packed.face_chart) == [0, 0, 1, 1, 2]
    assert packed.overlapping_face_pairs == 0
    assert ricci.find_uv_overlaps(packed.uv, faces).count == 0
    assert packed.uv.min() >= 0.025 - 1e-12 and packed.uv.max() <= 0.975 + 1e-12
    with pytest.raises(ricci.InvalidInput):
        ricci.pack_charts(layout, faces, options=ricci.ChartPackingOptions(gutter=-1))


def test_angle_polish_moves_the_interior_only(icosphere):
    V, F = icosphere
    cones = {0: math.pi, 5: math.pi, 9: math.pi, 11: math.pi}
    polished = ricci.parameterize(V, F, cones=cones)
    exact = ricci.parameterize(V, F, cones=cones, polish=False)
    assert polished.converged and exact.converged
    assert polished.polish.moved_vertices > 0 and exact.polish.moved_vertices == 0
    assert polished.polish.angle_distortion_after < polished.polish.angle_distortion_before
    # The positions from before the polish are the unpolished layout, bit for bit.
    np.testing.assert_array_equal(polished.polish.uv, exact.layout.uv)
    # Seam and cone vertices (on an edge of one uv face) did not move.
    t = exact.uv_triangles
    edges = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    seams = np.unique(unique[counts == 1])
    assert len(seams) > 0
    np.testing.assert_array_equal(polished.layout.uv[seams], exact.layout.uv[seams])
    _check_uv(polished)
    # The function itself, on the unpolished layout, does what the pipeline did.
    mesh = ricci.Mesh(V, F)
    again = ricci.polish_angles(mesh, t, exact.layout.uv)
    np.testing.assert_array_equal(again.uv, polished.layout.uv)
    with pytest.raises(ricci.InvalidInput):
        ricci.polish_angles(mesh, t[:3], exact.layout.uv)


def test_routes_name_how_each_component_was_laid_out():
    # Genus 12 with one hole: no cone is needed, but the flat metric with free boundary spans
    # more scale than double precision lays out; the component goes to the charts route.
    V, F = ricci.generate.surface_with_holes(12, 1, 16)
    param = ricci.parameterize(V, F)
    assert param.converged, param.message
    assert [r.method for r in param.routes] == [ricci.ComponentMethod.Charts]
    route = param.routes[0]
    assert route.charts >= 2 and route.flipped == 0 and "close up" in route.why
    assert param.distortion.flipped_faces == 0
    # Without the charts the exact map comes back as it is, and says it did not close up.
    exact = ricci.parameterize(V, F, charts=False)
    assert [r.method for r in exact.routes] == [ricci.ComponentMethod.Flow]
    assert exact.layout_error > 1e-6
    # A torus goes by the flow; untangle=False changes nothing there.
    T = ricci.generate.torus(24, 10)
    torus = ricci.parameterize(*T, untangle=False)
    assert [r.method for r in torus.routes] == [ricci.ComponentMethod.Flow]
    assert torus.routes[0].why == "" and torus.untangle.moved_vertices == 0
    with pytest.raises(ricci.InvalidInput):
        ricci.parameterize(V, F, geometry="hyperbolic", charts=False)


def test_few_cones_on_genus_two_are_refined_on_the_flow():
    # Two cones cannot meet the selection's bounds on genus 2: two candidate sets are measured
    # on the flow and the better one's curvatures refined there (ConeRefinementReport).
    V, F = ricci.generate.closed_surface(2, 8)
    r = ricci.parameterize(V, F, cones=2)
    assert r.converged, r.message
    refinement = r.routes[0].pipeline.cone_refinement
    assert refinement.ran and refinement.flows >= 2
    assert refinement.refined_energy <= min(refinement.selected_energy, refinement.level_energy)
    assert len(r.cones) == 2
    assert abs(sum(c.curvature for c in r.cones) - 2 * np.pi * -2) < 1e-9
    many = ricci.parameterize(V, F, cones=8)
    assert not many.routes[0].pipeline.cone_refinement.ran


def test_free_seams_keep_one_length_per_seam_edge():
    V, F = ricci.generate.closed_surface(2, 24)
    rigid = ricci.parameterize(V, F, cones=4)
    free = ricci.parameterize(V, F, cones=4, seams="free")
    assert free.converged, free.message
    _check_uv(free)
    # Each seam edge's two uv copies have one length (rigid seams: related by a rigid motion).
    uv, tri, tv = free.uv, free.uv_triangles, free.triangles
    lengths = {}
    worst = 0.0
    for f in range(len(tv)):
        for k in range(3):
            a, b = tv[f, k], tv[f, (k + 1) % 3]
            length = np.linalg.norm(uv[tri[f, k]] - uv[tri[f, (k + 1) % 3]])
            key = (min(a, b), max(a, b))
            if key in lengths:
                worst = max(worst, abs(lengths[key] - length) / max(length, lengths[key]))
            else:
                lengths[key] = length
    assert worst < 1e-9
    seams = free.routes[0].pipeline.seam_curvature
    assert seams.vertices > 0 and seams.max > 1e-3
    assert rigid.routes[0].pipeline.seam_curvature.max < 1e-8
    assert free.distortion.area_distortion_energy < 0.5 * rigid.distortion.area_distortion_energy
    assert ricci.ParamOptions().seams == ricci.SeamMode.Rigid
    with pytest.raises(ricci.InvalidInput):
        ricci.parameterize(V, F, seams="bent")
