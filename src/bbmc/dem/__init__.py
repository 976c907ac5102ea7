"""The block engine: a UDEC-style explicit 2D rigid-block DEM with Barton-Bandis joints.

`docs/architecture.md` has a table of its modules and follows one time step through them.
"""
