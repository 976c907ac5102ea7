"""Goodman & Bray's (1976) limit-equilibrium analysis of block toppling on a stepped base.

The method as Hoek & Bray (*Rock Slope Engineering*, 3rd ed. 1981, ch. 10) and Wyllie & Mah (*Rock
Slope Engineering: Civil and Mining*, 4th ed. 2004, section 9.4) teach it, with RocTopple's inputs:

* ``geometry``: the block system, from RocTopple's angles and spacing (``slope_blocks``), from the
  regular system's constants (``regular_system``) or from measured heights (``BlockSystem``);
* ``loads``: support forces (``BlockSupport``, ``face_support``) and joint water (``BlockWater``,
  ``phreatic_water``);
* ``march``: the force each block needs from the one below, from the top block down (``toe_force``);
* ``table``: every block's forces and mode at one pair of friction angles (``toppling_forces``);
* ``safety``: the factor of safety, the least factor on friction at which the system fails
  (``factor_of_safety``, ``limiting_friction``), and the toe support a slope needs
  (``horizontal_toe_support``).

Units: SI inside and out (m, rad, γ in N/m³, forces in N per metre of slope). The sources, the rules
the retrieved texts leave open and the checks: docs/reference/toppling-method.md.
"""

from bbmc.slope.toppling.geometry import (
    BlockSystem,
    crest_block_number,
    regular_block_heights,
    regular_constants,
    regular_system,
    slope_blocks,
)
from bbmc.slope.toppling.loads import (
    WATER_UNIT_WEIGHT,
    BlockSupport,
    BlockWater,
    face_support,
    phreatic_water,
)
from bbmc.slope.toppling.march import MODE_NAMES, SLIDES, STABLE, TOPPLES, toe_force
from bbmc.slope.toppling.safety import factor_of_safety, fails, horizontal_toe_support, limiting_friction
from bbmc.slope.toppling.table import TopplingTable, toppling_forces

__all__ = [
    "MODE_NAMES",
    "SLIDES",
    "STABLE",
    "TOPPLES",
    "WATER_UNIT_WEIGHT",
    "BlockSupport",
    "BlockSystem",
    "BlockWater",
    "TopplingTable",
    "crest_block_number",
    "face_support",
    "factor_of_safety",
    "fails",
    "horizontal_toe_support",
    "limiting_friction",
    "phreatic_water",
    "regular_block_heights",
    "regular_constants",
    "regular_system",
    "slope_blocks",
    "toe_force",
    "toppling_forces",
]
