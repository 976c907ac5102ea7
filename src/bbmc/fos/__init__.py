"""Analyses that drive the block engine to a factor of safety: shear-strength reduction
(`strength_reduction`) and the support design that reaches a target FS (`design`)."""
