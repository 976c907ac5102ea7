"""Kinematic analysis of a rock slope on the stereonet (Markland's test and its successors, as
Rocscience's Dips after Hudson & Harrison 1997): the criteria of each mode, their tallies for one
face, the sweep of faces around the compass and through dips, and the probability of each mode from
the sets' Fisher distributions. Reference: docs/reference/kinematics.md."""
