"""The numbers the wedge's figures show, as tables for CSV (units in the column names, as bbmc's CSVs
carry them): the vertices and the forces of `wedge_figures.wedge_figure`.

* vertices: O (toe), C1, C2 (crest), T (top), or with a tension crack P, Q, R in T's place
  (`bbmc.slope.wedge.geometry`), east_m, north_m, up_m;
* forces: each force drawn, its symbol, size [kN], trend and plunge [deg] (plunge downward positive, a
  force pointing up has a negative plunge: `loads.force_vector`'s convention) and components east,
  north, up [kN];
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from bbmc.geometry.orientation import trend_and_plunge, wrapped_azimuth
from bbmc.outputs.wedge_figures import KN, wedge_forces
from bbmc.outputs.wedge_vtk import one_wedge
from bbmc.slope.wedge.analysis import WedgeAnalysis
from bbmc.slope.wedge.geometry import WedgeGeometry
from bbmc.slope.wedge.support import Bolt


def vertex_table(geometry: WedgeGeometry, index: tuple[int, ...] = ()) -> pd.DataFrame:
    """The vertices [m] of the wedge at `index` (module docstring)."""
    g = one_wedge(geometry, index)
    names = ["O", "C1", "C2", *(("P", "Q", "R") if g.has_crack else ("T",))]
    east, north, up = np.asarray(g.vertices).T
    return pd.DataFrame({"vertex": names, "east_m": east, "north_m": north, "up_m": up})


def force_table(
    analysis: WedgeAnalysis, bolts: Sequence[Bolt] = (), index: tuple[int, ...] = ()
) -> pd.DataFrame:
    """The forces the 3D figure draws on the wedge at `index` (module docstring)."""
    forces = wedge_forces(analysis, bolts, index)
    vectors = np.array([vector for _, _, vector, _ in forces]) / KN
    trend, plunge = trend_and_plunge(vectors)  # of the axis, turned down: turn upward forces back
    rising = vectors[:, 2] > 0.0
    trend, plunge = np.where(rising, wrapped_azimuth(trend + np.pi), trend), np.where(rising, -plunge, plunge)
    return pd.DataFrame(
        {
            "force": [name for _, name, _, _ in forces],
            "symbol": [symbol for symbol, _, _, _ in forces],
            "size_kN": np.linalg.norm(vectors, axis=1),
            "trend_deg": np.degrees(trend),
            "plunge_deg": np.degrees(plunge),
            "east_kN": vectors[:, 0],
            "north_kN": vectors[:, 1],
            "up_kN": vectors[:, 2],
        }
    )
