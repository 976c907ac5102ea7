"""The 3D block engine: convex polyhedra, explicit central differences, rotation by unit quaternions.

Built part by part (issue 36); `layout` names the block array's columns and `motion` moves the blocks.
"""
