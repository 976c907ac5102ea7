"""Rock masses as they are mapped: a slope profile (polyline or benches), joint sets given by their
statistics, cut into convex blocks whose edges say what they are (docs/rock-mass.md)."""

from bbmc.rockmass.config import RockMassConfig
from bbmc.rockmass.generate import GeometryError, RockMass, SetSample, from_file, generate

__all__ = ["GeometryError", "RockMass", "RockMassConfig", "SetSample", "from_file", "generate"]
