"""The shear box set up with a shear config's parameters (`Bench`): builds the stress-controlled and
constant-velocity tests, runs them, and keeps the scenes it built."""

from __future__ import annotations

import pandas as pd
import yaml

from bbmc.paper_inputs import parameters
from bbmc.shear import box
from bbmc.shear.config import Config


class Bench:
    """The shear box with this config's parameters: builds and runs the tests."""

    def __init__(self, config: Config, inputs: dict[str, pd.DataFrame]) -> None:
        self.config = config
        self.strength, self.stiffness = parameters(config, inputs)
        self.density = float(inputs["table2"]["density_kg_per_m3"].iloc[0])
        self.scenes: dict[str, str] = {}

    def law(self, shear: dict) -> dict:
        """The joint law with eq 15's strength, eq 8's K_n and this shear-stiffness entry."""
        return box.joint_law(shear, self.strength, self.stiffness, self.config.joint_options)

    def full_law(self, sigma_n: float) -> dict:
        """The full Barton-Bandis joint at sigma_n [Pa] (`box.mobilized_joint_law`)."""
        c = self.config
        return box.mobilized_joint_law(self.strength, c.full_joint, self.stiffness, c.specimen, sigma_n)

    def paper_law(self, kind: box.ShearLaw, sigma_n: float) -> dict:
        return self.law(box.shear_stiffness_law(kind, sigma_n, self.stiffness))

    def stress_test(self, name: str, law: dict, sigma_n: float, tau: float, keep: bool = True) -> box.Outcome:
        c = self.config
        scene = box.stress_controlled_scene(
            name, c.specimen, c.stress_controlled, self.density, law, sigma_n, tau
        )
        if keep:
            self.scenes[f"scenes/{name}.yaml"] = yaml.safe_dump(scene, sort_keys=False)
        return box.run_stress_controlled(scene)

    def velocity_test(
        self, name: str, law: dict, sigma_n: float, update_interval: int | None = None
    ) -> pd.DataFrame:
        """A constant-velocity test with `law`; `update_interval`: the law's, if not the config's."""
        c = self.config
        run = c.constant_velocity
        if update_interval is not None:
            run = run.model_copy(update={"update_interval_steps": update_interval})
        scene = box.constant_velocity_scene(name, c.specimen, run, self.density, law, sigma_n)
        self.scenes[f"scenes/{name}.yaml"] = yaml.safe_dump(scene, sort_keys=False)
        return box.run_constant_velocity(scene)
