"""ricci.flow: targets, cones, solvers, the progress callback and the option classes."""

import copy
import math

import numpy as np
import pytest

import ricci

TWO_PI = 2 * math.pi


def test_torus_flat_newton(torus):
    V, F = torus
    result = ricci.flow(V, F, tolerance=1e-10)
    assert result.converged
    assert result.status == ricci.FlowStatus.Converged
    assert result.max_error <= 1e-10
    n, e = len(V), 1536
    assert result.u.shape == result.curvature.shape == result.target_curvature.shape == (n,)
    assert result.edges.shape == (e, 2) and result.lengths.shape == (e,)
    assert np.all(result.edges[:, 0] < result.edges[:, 1])
    assert np.all(result.lengths > 0)
    # Gauss-Bonnet: the curvature sums to 2 pi chi = 0 (compensated sums: well below 1e-9).
    assert abs(result.curvature.sum() - TWO_PI * 0) <= 1e-9
    np.testing.assert_allclose(result.curvature, 0, atol=1e-10)
    # One component, its history from iteration 0, timings, the fit error of the packing.
    assert len(result.history) == 1 and len(result.timings) == 1
    history = result.history[0]
    assert [r.iteration for r in history] == list(range(len(history)))
    assert history[-1].max_error == pytest.approx(result.max_error, rel=0, abs=0)
    assert history[0].max_error > history[-1].max_error
    assert result.timings[0].total > 0
    assert result.fit_error == 0  # vertex scaling starts from the input lengths exactly
    assert "reached" in result.message


def test_sphere_uniform_target_gauss_bonnet(icosphere):
    V, F = icosphere
    result = ricci.flow(V, F, target="uniform")
    assert result.converged
    assert abs(result.curvature.sum() - TWO_PI * 2) <= 1e-9
    np.testing.assert_allclose(result.curvature, 4 * math.pi / len(V), atol=1e-10)


def test_target_from_options_object(icosphere):
    V, F = icosphere
    options = ricci.MeshFlowOptions(target=ricci.TargetSpec(kind=ricci.TargetKind.Uniform))
    result = ricci.flow(V, F, options=options)
    assert result.converged
    np.testing.assert_allclose(result.curvature, 4 * math.pi / len(V), atol=1e-10)


def test_cones_as_list_dict_and_text_agree(icosphere):
    V, F = icosphere
    # The 12 icosahedron vertices with pi/3 each: 4 pi in total (chi = 2).
    as_list = ricci.flow(V, F, cones=[(v, math.pi / 3) for v in range(12)])
    as_dict = ricci.flow(V, F, cones={v: "pi/3" for v in range(12)})
    as_text = ricci.flow(V, F, cones=",".join(f"{v}:pi/3" for v in range(12)))
    as_cones = ricci.flow(V, F, cones=[ricci.Cone(v, math.pi / 3) for v in range(12)])
    for result in (as_list, as_dict, as_text, as_cones):
        assert result.converged and result.max_error <= 1e-10
        np.testing.assert_allclose(result.target_curvature[:12], math.pi / 3, rtol=1e-15)
        np.testing.assert_allclose(result.curvature[12:], 0, atol=1e-10)
        assert abs(result.curvature.sum() - TWO_PI * 2) <= 1e-9
    np.testing.assert_allclose(as_dict.u, as_list.u, rtol=0, atol=1e-12)


def test_values_target(torus):
    V, F = torus
    result = ricci.flow(V, F, target=np.zeros(len(V)))
    assert result.converged
    assert result.target.description != ""


def test_disk_boundary(tmp_path):
    V, F = ricci.generate.disk(6, 0.5)
    result = ricci.flow(V, F, target="disk")
    assert result.converged
    boundary = result.topology.is_boundary_vertex
    # chi = 1: the boundary takes 2 pi evenly, the interior is flat.
    np.testing.assert_allclose(result.curvature[boundary], TWO_PI / boundary.sum(), atol=1e-10)
    np.testing.assert_allclose(result.curvature[~boundary], 0, atol=1e-10)
    free = ricci.flow(V, F, boundary="free")
    assert free.converged and free.target.fixed[boundary].all()


def test_gradient_solver(torus):
    V, F = torus
    result = ricci.flow(V, F, solver="gradient", tolerance=1e-8)
    assert result.converged and result.max_error <= 1e-8
    # Exponential convergence takes many more steps than Newton's few.
    assert len(result.history[0]) > 50
    assert abs(result.curvature.sum()) <= 1e-9
    stopped = ricci.flow(V, F, solver="gradient", max_iterations=10)
    assert not stopped.converged
    assert stopped.status == ricci.FlowStatus.MaxIterations


def test_progress_callback_is_called(torus):
    V, F = torus
    records = []
    result = ricci.flow(V, F, progress=records.append)  # returns None: the flow goes on
    assert result.converged
    assert len(records) == len(result.history[0])
    assert all(isinstance(r, ricci.IterationRecord) for r in records)
    assert [r.iteration for r in records] == [r.iteration for r in result.history[0]]


def test_progress_callback_cancels(torus):
    V, F = torus
    seen = []

    def stop_after_first(record):
        seen.append(record.iteration)
        return record.iteration < 1

    result = ricci.flow(V, F, progress=stop_after_first)
    assert not result.converged
    assert result.status == ricci.FlowStatus.Cancelled
    assert seen[-1] == 1
    assert "cancel" in result.message


def test_progress_callback_exception_propagates(torus):
    V, F = torus

    def broken(record):
        raise ZeroDivisionError("from the callback")

    with pytest.raises(ZeroDivisionError, match="from the callback"):
        ricci.flow(V, F, progress=broken)


def test_option_classes_mirror_the_structs(torus):
    V, F = torus
    options = ricci.MeshFlowOptions(
        structure=ricci.StructureOptions(scheme="tangential"),
        flow=ricci.FlowOptions(solver=ricci.FlowSolver.Newton, tolerance=1e-6),
        target=ricci.TargetSpec(kind="flat"))
    assert options.structure.scheme == ricci.Scheme.Tangential
    assert options.flow.tolerance == 1e-6
    assert ricci.FlowOptions().tolerance == 1e-10  # the C++ default
    assert ricci.ParamOptions().flow.tolerance == 1e-12
    assert ricci.Scheme("vertex-scaling") == ricci.Scheme.VertexScaling
    options.flow.max_iterations = 50  # nested structs are references
    assert options.flow.max_iterations == 50
    before = copy.deepcopy(options)
    result = ricci.flow(V, F, options=options, tolerance=1e-9)
    assert result.converged and result.max_error <= 1e-9
    assert result.structure.structure.scheme == ricci.Scheme.Tangential
    assert options.flow.tolerance == before.flow.tolerance  # the caller's options are copied
    callback = lambda record: True  # noqa: E731
    options.flow.progress = callback
    assert options.flow.progress is callback
    assert "tolerance=1e-06" in repr(options.flow)


def test_schemes(icosphere):
    V, F = icosphere
    for scheme in ("thurston", "tangential", "inversive-distance", "vertex-scaling",
                   "virtual-radius"):
        result = ricci.flow(V, F, target="uniform", scheme=scheme)
        assert result.converged, (scheme, result.message)
        assert abs(result.curvature.sum() - TWO_PI * 2) <= 1e-9
