"""Geometry, the lowest layer: convex polygons and their mass properties (`polygons`), and the
orientations of planes and lines in 3D with their statistics (`orientation`). It imports nothing of
bbmc outside itself."""
