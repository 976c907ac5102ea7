"""Unit factors for the boundary (config keys, CSV columns, figure axes).

Multiply a boundary value by its factor to get SI; divide an SI value by it to print.
`2.0 * MPa` is 2e6 Pa; `k / MPa_per_mm` prints a stiffness given in Pa/m.
"""

import math

Pa = 1.0
kPa = 1.0e3
MPa = 1.0e6
GPa = 1.0e9
m = 1.0
mm = 1.0e-3
deg = math.pi / 180.0
Pa_per_m = 1.0
GPa_per_m = GPa / m
MPa_per_mm = MPa / mm
kPa_per_mm = kPa / mm
kN = 1.0e3
kN_per_m3 = kN / m**3  # a unit weight
per_mm = 1.0 / mm
