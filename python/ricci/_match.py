"""Shape matching and morphing: ``match`` and ``morph`` wrap ricci/match/match.hpp."""

import types

import numpy as np

from . import _arrays, _ricci


def _landmark_pairs(landmarks):
    if landmarks is None:
        return []
    pairs = np.asarray(landmarks)
    if pairs.size == 0:
        return []
    if pairs.ndim != 2 or pairs.shape[1] != 2 or not np.issubdtype(pairs.dtype, np.integer):
        raise ValueError("landmarks: expected an (n, 2) array of integer vertex pairs (i of A, j of B)")
    return [(int(i), int(j)) for i, j in pairs]


def match(VA, FA, VB, FB, *, landmarks=None, reverse=False, max_samples=4000):
    """Correspondence between two surfaces of the same topology (docs/matching.md): closed
    genus 0 on the unit sphere, disks on the unit disk, closed genus 1 on their flat tori,
    aligned there by landmarks (sphere: three or more fix a Moebius transformation; disk: a
    boundary pair and an interior pair) or, without, by the area's centre of mass and the
    rotation (translation on a torus) that best aligns the two conformal factors.

    VA, FA / VB, FB: (n, 3) float positions and (m, 3) integer triangles of A and B.
    landmarks: (k, 2) integer pairs, vertex i of A goes to vertex j of B (0-based).
    reverse: also map B's vertices onto A.

    Returns a namespace: ``faces`` (nA,) faces of B and ``barycentric`` (nA, 3) weights of their
    corners, ``positions`` (nA, 3) the points of B they give; with reverse, ``reverse_faces``,
    ``reverse_barycentric``, ``reverse_positions``; ``domain`` ("sphere", "disk", "torus"),
    ``converged``, ``message``, ``method``, ``factor_mismatch``, ``landmark_distances``,
    ``landmark_rms``, ``landmark_max``, the tori's ``modulus_a``, ``modulus_b``,
    ``modulus_distance``, ``affine_map``, ``affine_distortion``, and the map's
    ``angle_distortion_mean`` / ``_max``, ``log_area_stddev``, ``flipped_faces``, ``seconds``.

    Raises ValueError for arrays of the wrong shape or dtype, InvalidInput for other topologies,
    different topologies or landmarks out of range, TopologyError for non-manifold meshes.
    """
    result = _ricci.match_surfaces(_arrays.mesh(VA, FA), _arrays.mesh(VB, FB),
                                   _landmark_pairs(landmarks), bool(reverse), int(max_samples))
    return types.SimpleNamespace(**result)


def morph(VA, FA, VB, FB, *, frames=8, landmarks=None, rigid=True):
    """Morph from A to B along their correspondence (``match``): an array (frames, nA, 3) of
    positions on A's faces FA, from A (frame 0) to the points of B that A's vertices map to
    (the last frame), linearly; with rigid, B is first moved by the rotation and translation
    that best fit it onto A. Raises as ``match``, and InvalidInput when frames < 2."""
    m = match(VA, FA, VB, FB, landmarks=landmarks)
    if not m.converged:
        raise _ricci.Error("morph: the canonical maps did not converge: " + m.message)
    return _ricci.morph_frames(_arrays.mesh(VA, FA), np.asarray(m.positions, dtype=np.float64),
                               int(frames), bool(rigid))
