"""What a sweep evaluates: a batch of samples (a table of inputs by dotted path) in, a table of outputs
out, one row per sample, in the same order. A sample whose model fails gets its error text and no
output, and the others go on; its `outcome` says why it has no output:

* `invalid`: a scene sample whose own scene is at fault, chiefly its geometry: it cannot be built
  (blocks overlapping, joint sets that make no block: a `ConfigError`), or its run is refused as bad
  input (a block that finds no equilibrium even with every strength x 1e6: `SimulationError` with
  `bad_input`). Its error names the key at fault.
* `failed_run`: any other error (an engine fault, a limit-equilibrium model's impossible geometry).

A sample with an output is `valid`; one whose FS is below 1 is a failure like any other (a scene that
cannot stand under its own strengths gets FS < 1 from its elastic start, `bbmc.fos.strength_reduction`).

Models are plain frozen dataclasses holding only the base's data, so they pickle to worker processes
and dask workers; numba's compiled kernels come from its on-disk cache in each process.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from bbmc import units
from bbmc.config import ConfigError
from bbmc.dem.model import built_scene
from bbmc.dem.solver import SimulationError, simulate
from bbmc.fos.strength_reduction import factor_of_safety
from bbmc.scene.paths import get_path as get_path  # the sweep's callers read paths from here
from bbmc.scene.paths import set_path
from bbmc.slope import planar, toppling
from bbmc.slope.limit_equilibrium import G

FS = "factor_of_safety"
ERROR = "error"
OUTCOME = "outcome"
VALID, INVALID, FAILED_RUN = "valid", "invalid", "failed_run"


def _errors(n: int) -> np.ndarray:
    return np.full(n, "", dtype=object)


def _limit_equilibrium_table(fs: np.ndarray, errors: np.ndarray, index: pd.Index) -> pd.DataFrame:
    """A limit-equilibrium batch's outputs: a sample with an error is a failed run."""
    outcome = np.where(errors == "", VALID, FAILED_RUN)
    return pd.DataFrame({FS: fs, ERROR: errors, OUTCOME: outcome}, index=index)


def scene_at_fault(error: Exception) -> bool:
    """Whether a scene sample's error lies in its own scene (its geometry): invalid, not a failed run."""
    return isinstance(error, ConfigError) or (isinstance(error, SimulationError) and error.bad_input)


@dataclass(frozen=True)
class PlanarModel:
    """Hoek & Bray's planar limit equilibrium (`bbmc.slope.planar`), the whole batch in one vectorised
    call; a batch with an impossible sample is evaluated sample by sample, so that only that one fails."""

    base: dict  # the config's `base`, as a plain mapping in its own units

    def _fs(self, inputs: pd.DataFrame) -> np.ndarray:
        values = {}
        for key in ("height_m", "face_deg", "plane_deg", "crack_depth_m", "water_fill", "unit_weight_kN_m3",
                    "seismic_coefficient"):  # fmt: skip
            values[key] = inputs[key].to_numpy() if key in inputs else self.base[key]
        strength = {
            key: inputs[f"strength.{key}"].to_numpy() if f"strength.{key}" in inputs else value
            for key, value in self.base["strength"].items()
        }
        support = None
        if self.base.get("support") is not None:
            given = {
                key: inputs[f"support.{key}"].to_numpy() if f"support.{key}" in inputs else value
                for key, value in self.base["support"].items()
            }
            support = planar.Support(
                np.asarray(given["force_kN_per_m"]) * 1e3, np.radians(given["angle_deg"]), given["form"]
            )
        z = np.asarray(values["crack_depth_m"], dtype=float)
        forces = planar.planar_forces(
            values["height_m"],
            np.radians(values["face_deg"]),
            np.radians(values["plane_deg"]),
            z,
            np.asarray(values["water_fill"]) * z,
            np.asarray(values["unit_weight_kN_m3"]) * 1e3,
            values["seismic_coefficient"],
        )
        if strength["law"] == "mohr_coulomb":
            friction = (
                np.radians(strength["friction_deg"])
                if strength["friction_deg"] is not None
                else np.arctan(strength["tan_friction"])
            )
            fs = planar.factor_of_safety_mohr_coulomb(
                forces, np.asarray(strength["cohesion_kPa"]) * units.kPa, friction, support
            )
        else:
            fs = planar.factor_of_safety_barton_bandis(
                forces,
                strength["jrc"],
                np.asarray(strength["jcs_MPa"]) * units.MPa,
                np.radians(strength["phi_b_deg"]),
                np.radians(strength["phi_max_deg"]),
                support,
            )
        return np.broadcast_to(fs, (len(inputs),)).astype(float)

    def __call__(self, inputs: pd.DataFrame) -> pd.DataFrame:
        errors = _errors(len(inputs))
        try:
            fs = self._fs(inputs)
        except ValueError:
            fs = np.full(len(inputs), math.nan)
            for k in range(len(inputs)):
                try:
                    fs[k] = self._fs(inputs.iloc[[k]])[0]
                except ValueError as error:
                    errors[k] = str(error)
        return _limit_equilibrium_table(fs, errors, inputs.index)


SUPPORT_KEYS = ("block", "force_kN_per_m", "angle_deg", "height_m", "level_m")  # a toppling base's support


DEFAULT_UNIT_WEIGHT_KN_M3 = 26.0  # a toppling base's unit weight without a density or unit weight


@dataclass(frozen=True)
class TopplingModel:
    """Goodman & Bray's toppling (`bbmc.slope.toppling`): the block system built once per geometry, its
    FS broadcast over the batch's friction angles; a geometry that forms no system fails its samples.
    The unit weight is density x g if the base (or the sample) gives a density, else unit_weight_kN_m3,
    else 26 kN/m^3; water_level_m puts a horizontal phreatic line that high above the toe."""

    base: dict

    def _column(self, inputs: pd.DataFrame, key: str, default: object = None) -> np.ndarray:
        value = self.base.get(key, default)
        return np.asarray(inputs[key] if key in inputs else np.full(len(inputs), value, dtype=object))

    def _support(self, inputs: pd.DataFrame) -> dict[str, np.ndarray]:
        """The support's values per sample (zero force without a support)."""
        given = {"level_m": None, **(self.base.get("support") or dict.fromkeys(SUPPORT_KEYS, 0.0))}
        given["level_m"] = -math.inf if given["level_m"] is None else given["level_m"]  # -inf: by block
        return {
            key: np.asarray(
                inputs[f"support.{key}"] if f"support.{key}" in inputs else np.full(len(inputs), given[key]),
                dtype=float,
            )
            for key in SUPPORT_KEYS
        }

    def _unit_weight(self, inputs: pd.DataFrame) -> np.ndarray:
        """[kN/m^3] per sample."""
        density = self._column(inputs, "density_kg_m3")
        weight = self._column(inputs, "unit_weight_kN_m3")
        given = np.array([w if w is not None else DEFAULT_UNIT_WEIGHT_KN_M3 for w in weight], dtype=float)
        return np.array(
            [g if d is None else float(d) * G / 1e3 for d, g in zip(density, given, strict=True)], dtype=float
        )

    def __call__(self, inputs: pd.DataFrame) -> pd.DataFrame:
        keys = ("width_m", "base_dip_deg", "crest_block", "a1_m", "a2_m", "b_m")
        values = {k: inputs[k].to_numpy() if k in inputs else np.full(len(inputs), self.base[k]) for k in
                  (*keys, "friction_deg", "side_friction_deg")}  # fmt: skip
        support = self._support(inputs)
        level = self._column(inputs, "water_level_m")
        wet = np.array([-math.inf if v is None else float(v) for v in level])  # -inf: dry (unique, not nan)
        fs, errors = np.full(len(inputs), math.nan), _errors(len(inputs))
        columns = [np.asarray(values[k], dtype=float) for k in keys]
        columns += [self._unit_weight(inputs), wet] + [support[k] for k in SUPPORT_KEYS]
        geometry = np.column_stack(columns)
        for row in np.unique(geometry, axis=0):
            rows = np.all(geometry == row, axis=1)
            width, dip, crest, a1, a2, b, unit_weight, water_level = row[: len(keys) + 2]
            block, force, angle, height, level = row[len(keys) + 2 :]
            try:
                system = toppling.regular_system(width, math.radians(dip), int(crest), a1, a2, b)
                held = (
                    None
                    if force <= 0
                    else toppling.BlockSupport.on_block(
                        system, int(block), force * 1e3, math.radians(angle), height
                    )
                    if level == -math.inf
                    else toppling.face_support(
                        system, level, force * 1e3, math.radians(angle) - system.base_dip
                    )
                )
                water = (
                    None
                    if water_level == -math.inf
                    else toppling.phreatic_water(system, [-1e9, 1e9], [water_level, water_level])
                )
                side = values["side_friction_deg"]
                fs[rows] = toppling.factor_of_safety(
                    system,
                    np.radians(np.asarray(values["friction_deg"], dtype=float)[rows]),
                    None if side[0] is None else np.radians(np.asarray(side, dtype=float)[rows]),
                    held,
                    unit_weight * 1e3,
                    water,
                )
            except ValueError as error:
                errors[rows] = str(error)
        return _limit_equilibrium_table(fs, errors, inputs.index)


@dataclass(frozen=True)
class SceneModel:
    """A block scene with each sample's values set at their paths: its factor of safety by strength
    reduction (`scene_fos`), or a monitor's value at the end of `bbmc run` and whether a stop by
    displacement ended it (`scene_run`)."""

    scene: dict  # the scene file, parsed
    name: str  # for messages
    kind: str
    monitor: str | None = None

    def _one(self, values: pd.Series) -> dict[str, object]:
        tree = copy.deepcopy(self.scene)
        for path, value in values.items():
            set_path(tree, str(path), float(value))
        model = built_scene(tree, self.name)
        if self.kind == "scene_fos":
            return {FS: factor_of_safety(model).factor_of_safety}
        result = simulate(model)
        summary = dict(zip(result.summary["quantity"], result.summary["value"], strict=True))
        return {
            self.monitor: float(result.history[self.monitor].iloc[-1]),
            "stopped_by_displacement": bool(summary["stopped_by_displacement"]),
        }

    def __call__(self, inputs: pd.DataFrame) -> pd.DataFrame:
        rows = []
        for _, values in inputs.iterrows():
            try:
                row = {**self._one(values), ERROR: "", OUTCOME: VALID}
            except (ConfigError, SimulationError, ValueError, KeyError) as error:
                outcome = INVALID if scene_at_fault(error) else FAILED_RUN
                row = {ERROR: f"{type(error).__name__}: {error}", OUTCOME: outcome}
            rows.append(row)
        columns = [FS] if self.kind == "scene_fos" else [self.monitor, "stopped_by_displacement"]
        return pd.DataFrame(rows, index=inputs.index).reindex(columns=[*columns, ERROR, OUTCOME])
