"""bbmc: the Barton-Bandis joint criterion inside a Mohr-Coulomb slip model, reproduced against the paper.

Sign convention, stated once: compression is positive (sigma_n > 0 closes a joint); shear stress
tau >= 0 is its magnitude. Inside the package every quantity is SI (Pa, m, rad, Pa/m); MPa, kPa, mm,
GPa/m and degrees appear only at the boundary (YAML keys, CSV columns, figure axes), see `bbmc.units`.
"""

from bbmc import kernel_cache

__version__ = "0.1.0"

kernel_cache.use_keyed_cache()  # before any kernel is decorated: see `bbmc.kernel_cache`
