"""The block engine: a UDEC-style explicit 2D rigid-block DEM with Barton-Bandis joints.

`docs/architecture.md` has a table of its modules and follows one time step through them.
"""

import os

# numba's OpenMP threads sleep between parallel loops instead of spinning: a spinning thread takes a core
# from the serial parts of the step and from every other process (measured on 2 shared cores: a
# 10,000-block step took 15-30 ms on 2 spinning threads, 2.6 ms on 2 sleeping ones)
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
