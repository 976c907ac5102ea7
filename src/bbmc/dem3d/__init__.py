"""The 3D block engine: rigid convex polyhedra on the joint laws of `bbmc.laws` (issue 36)."""
