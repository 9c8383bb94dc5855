"""Generated meshes with known topology (mesh/generate.hpp). Each function returns ``(V, F)``:
float64 (n, 3) positions and int32 (m, 3) counter-clockwise triangles."""

from . import _arrays, _ricci


def tetrahedron(edge_length=1.0):
    """Regular tetrahedron centred at the origin (4 vertices, chi = 2, curvature pi at each)."""
    return _arrays.arrays(_ricci.make_tetrahedron(edge_length))


def icosphere(subdivisions, radius=1.0):
    """Icosahedron subdivided ``subdivisions`` times on a sphere (10 4^s + 2 vertices)."""
    return _arrays.arrays(_ricci.make_icosphere(subdivisions, radius))


def disk(rings, bulge=0.0):
    """Unit disk of ``rings`` rings (1 + 3 r (r + 1) vertices, one boundary loop), lifted to the
    cap z = bulge (1 - x^2 - y^2)."""
    return _arrays.arrays(_ricci.make_disk(rings, bulge))


def torus(major, minor, major_radius=1.0, minor_radius=0.4):
    """Torus of revolution of ``major`` by ``minor`` segments (vertex (i, j) at index
    i * minor + j; 2 major minor faces; chi = 0)."""
    return _arrays.arrays(_ricci.make_torus(major, minor, major_radius, minor_radius))


def closed_surface(genus, resolution=12):
    """A closed orientable surface of the given genus (chi = 2 - 2 genus)."""
    return _arrays.arrays(_ricci.make_closed_surface(genus, resolution))


def surface_with_holes(genus, holes, resolution=12):
    """A surface of the given genus with ``holes`` boundary loops (chi = 2 - 2 g - holes)."""
    return _arrays.arrays(_ricci.make_surface_with_holes(genus, holes, resolution))


def grid(nx, ny, width=1.0, height=1.0):
    """Flat grid [0, width] x [0, height] of nx by ny quads split into triangles."""
    return _arrays.arrays(_ricci.make_grid(nx, ny, width, height))
