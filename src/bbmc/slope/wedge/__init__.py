"""Wedge failure of a rock slope: two joint planes, the face and the upper surface (issue 35)."""
