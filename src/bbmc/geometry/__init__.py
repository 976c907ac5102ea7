"""Geometry, the lowest layer: convex polygons and their mass properties (`polygons`), convex polyhedra,
their mass properties and cutting (`polyhedra`, `polyhedron_mass`, `polyhedron_cutting`), and the
orientations of planes and lines in 3D with their statistics (`orientation`). It imports nothing of
bbmc outside itself."""
