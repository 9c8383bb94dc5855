"""Shape and dtype checks of the Python layer, and C++ exceptions as Python exceptions."""

import numpy as np
import pytest

import ricci


def test_exception_hierarchy():
    assert issubclass(ricci.InvalidInput, ValueError)
    assert issubclass(ricci.InvalidInput, ricci.Error)
    assert issubclass(ricci.TopologyError, ricci.InvalidInput)
    assert issubclass(ricci.IoError, OSError)
    assert issubclass(ricci.SolverError, RuntimeError)
    assert ricci.InvalidInput.__module__ == "ricci"


@pytest.mark.parametrize("function", [ricci.info, ricci.flow, ricci.parameterize])
def test_vertices_of_wrong_shape(function, tetrahedron):
    _, F = tetrahedron
    with pytest.raises(ValueError, match=r"V must be an \(n, 3\) float array, got shape \(5, 2\)"):
        function(np.zeros((5, 2)), F)
    with pytest.raises(ValueError, match=r"got shape \(12,\)"):
        function(np.zeros(12), F)


def test_triangles_of_wrong_shape_or_dtype(tetrahedron):
    V, F = tetrahedron
    with pytest.raises(ValueError, match=r"F must be an \(m, 3\) integer array, got shape \(2, 4\)"):
        ricci.flow(V, np.zeros((2, 4), dtype=int))
    with pytest.raises(ValueError, match="F must be an .* integer array, got dtype float64"):
        ricci.flow(V, F.astype(float))
    with pytest.raises(ValueError, match="V must be .* got dtype complex128"):
        ricci.info(V.astype(complex), F)
    with pytest.raises(ValueError, match="32-bit"):
        ricci.info(V, F.astype(np.int64) + 2**40)


def test_conversions_are_accepted(tetrahedron):
    V, F = tetrahedron
    # Integer positions, a non-contiguous view, int64 triangles, nested lists.
    ints = ricci.info(np.round(V * 1000).astype(np.int64), F.astype(np.int64))
    assert ints.faces == 4 and ints.genus == 0
    wide = np.zeros((4, 6))
    wide[:, ::2] = V
    view = wide[:, ::2]
    assert not view.flags["C_CONTIGUOUS"]
    assert ricci.info(view, F).edges == 6
    assert ricci.info(V.tolist(), F.tolist()).edges == 6
    result = ricci.flow(np.asfortranarray(V), F.astype(np.uint16), target="uniform")
    assert result.converged


def test_non_manifold_mesh_raises_topology_error(non_manifold):
    V, F = non_manifold
    with pytest.raises(ricci.TopologyError, match="non-manifold edge"):
        ricci.flow(V, F)
    with pytest.raises(ricci.TopologyError):
        ricci.parameterize(V, F)
    with pytest.raises(ValueError):  # TopologyError is an InvalidInput is a ValueError
        ricci.validate(V, F)


def test_index_out_of_range_is_invalid_input(tetrahedron):
    V, F = tetrahedron
    F = F.copy()
    F[0, 0] = 9
    with pytest.raises(ricci.InvalidInput, match="9"):
        ricci.flow(V, F)


def test_cones_breaking_gauss_bonnet(torus):
    V, F = torus
    with pytest.raises(ricci.InvalidInput, match="Gauss-Bonnet"):
        ricci.flow(V, F, cones=[(0, np.pi / 2)])


def test_bad_option_values(torus):
    V, F = torus
    with pytest.raises(ricci.InvalidInput, match="thurston"):  # lists the valid names
        ricci.flow(V, F, scheme="no-such-scheme")
    with pytest.raises(ricci.InvalidInput):
        ricci.flow(V, F, solver="bisection")
    with pytest.raises(ricci.InvalidInput):
        ricci.flow(V, F, target="round")
    with pytest.raises(ValueError, match=r"target must be an \(512,\) float array"):
        ricci.flow(V, F, target=np.zeros(7))
    with pytest.raises(ValueError, match="cones need a flat target"):
        ricci.flow(V, F, target="uniform", cones={0: 1.0})
    with pytest.raises(ValueError, match="cone vertex must be an integer"):
        ricci.flow(V, F, cones=[(0.5, 1.0)])
    with pytest.raises(ValueError, match="cone count"):
        ricci.parameterize(V, F, cones=0)
    with pytest.raises(ricci.InvalidInput, match="out of range|not a vertex|vertex 100000"):
        ricci.flow(V, F, cones={100000: 0.0})


def test_unknown_option_field_is_type_error():
    with pytest.raises(TypeError, match="unknown field 'tolerence'.*tolerance"):
        ricci.FlowOptions(tolerence=1e-3)


def test_refusals_name_the_keyword_that_works(torus):
    V, F = ricci.generate.icosphere(2)
    with pytest.raises(ricci.InvalidInput) as caught:
        ricci.flow(V, F, target="flat")
    assert caught.value.fixes == [("target", "natural"), ("target", "uniform")]
    assert 'try: target="natural", or target="uniform"' in str(caught.value)
    with pytest.raises(ricci.InvalidInput) as caught:
        ricci.parameterize(V, F, cones="none")
    assert caught.value.fixes == [("cones", "auto")]
    with pytest.raises(ricci.InvalidInput) as caught:
        ricci.parameterize(V, F, cones=1)
    assert 'cones=4, or cones="auto"' in str(caught.value)
    with pytest.raises(ricci.InvalidInput) as caught:
        ricci.parameterize(*torus, cones="one")
    assert caught.value.fixes == [("cones", "needed"), ("cones", "auto")]
    # An error with nothing to suggest has an empty list.
    with pytest.raises(ricci.InvalidInput) as caught:
        ricci.flow(*torus, cones={100000: 0.0})
    assert caught.value.fixes == []
