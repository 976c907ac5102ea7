"""The 3D block engine: rigid convex polyhedra on the joint laws of `bbmc.laws` (issue 36), explicit
central differences, rotation by unit quaternions.

Built part by part: `layout` names the block array's columns and `motion` moves the blocks;
`contact_geometry`, `polygon_clip` and `broad_phase` find the contacts, their planes, overlap areas
and sub-contacts; `joint_laws` gives their strength, `contact_forces` their forces; `model` builds a
model from polyhedra and `solver` runs it (`build_model`, `time_step`, `run`).
"""
