"""Rock support: bolts, anchors and cables, their capacities, and the support that reaches a target FS."""
