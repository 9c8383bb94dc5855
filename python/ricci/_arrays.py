"""Shape and dtype checks of the arrays the package takes, with messages that name the argument.

Everything the C++ side receives goes through here: positions become C-contiguous float64
(n, 3), triangles C-contiguous int32 (m, 3).
"""

import numpy as np

from . import _ricci

_INT32_MAX = np.iinfo(np.int32).max


def vertices(V, name="V"):
    """V as a C-contiguous float64 (n, 3) array (integer arrays are converted)."""
    a = np.asarray(V)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name} must be an (n, 3) float array, got shape {a.shape}")
    if a.dtype.kind not in "fiu":
        raise ValueError(f"{name} must be an (n, 3) float array, got dtype {a.dtype}")
    return np.ascontiguousarray(a, dtype=np.float64)


def triangles(F, name="F"):
    """F as a C-contiguous int32 (m, 3) array; values must fit in int32 (range is checked by the
    C++ validation, which names the face)."""
    a = np.asarray(F)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name} must be an (m, 3) integer array, got shape {a.shape}")
    if a.dtype.kind not in "iu":
        raise ValueError(f"{name} must be an (m, 3) integer array, got dtype {a.dtype}")
    if a.size:
        outside = a.max() if a.max() > _INT32_MAX else a.min() if a.min() < -_INT32_MAX - 1 \
            else None
        if outside is not None:
            raise ValueError(f"{name} holds vertex index {outside}, beyond the 32-bit indices "
                             f"ricci uses")
    return np.ascontiguousarray(a, dtype=np.int32)


def per_vertex(values, n, name):
    """A float64 (n,) array with one value per vertex."""
    a = np.asarray(values)
    if a.ndim != 1 or a.shape[0] != n:
        raise ValueError(f"{name} must be an ({n},) float array with one value per vertex, "
                         f"got shape {a.shape}")
    if a.dtype.kind not in "fiu":
        raise ValueError(f"{name} must be an ({n},) float array, got dtype {a.dtype}")
    return np.ascontiguousarray(a, dtype=np.float64)


def mesh(V, F):
    """A C++ Mesh from checked V and F."""
    return _ricci.Mesh(vertices(V), triangles(F))


def arrays(mesh_):
    """(V, F) of a C++ Mesh as C-contiguous float64 and int32 arrays."""
    return (np.ascontiguousarray(mesh_.positions, dtype=np.float64),
            np.ascontiguousarray(mesh_.triangles, dtype=np.int32))
