"""A toppling study's model (`bbmc.sweep.models.TopplingModel`): the unit weight from the rock's density,
water from a level, and separate base and side friction, sample by sample as the sweep runs them."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from bbmc.slope import toppling as tp
from bbmc.sweep.config import Toppling
from bbmc.sweep.models import TopplingModel

BASE = {
    "kind": "toppling",
    "width_m": 10.0,
    "base_dip_deg": 30.0,
    "crest_block": 10,
    "a1_m": 5.0,
    "a2_m": 5.0,
    "b_m": 1.0,
    "friction_deg": 40.0,
    "support": {"block": 1, "force_kN_per_m": 2000.0, "angle_deg": 30.0, "height_m": 2.0},
}
SYSTEM = tp.regular_system(10.0, math.radians(30.0), 10, 5.0, 5.0, 1.0)
SUPPORT = tp.BlockSupport.on_block(SYSTEM, 1, 2e6, math.radians(30.0), 2.0)


def _fs(base: dict, inputs: dict) -> np.ndarray:
    model = TopplingModel(Toppling(**base).model_dump())
    return model(pd.DataFrame(inputs))["factor_of_safety"].to_numpy()


def test_the_unit_weight_follows_the_density():
    """2,700 kg/m³ × 9.81 = 26.487 kN/m³ (the supported FS depends on it); without either, 26 kN/m³."""
    friction = {"friction_deg": [36.0, 40.0]}
    dense = _fs({**BASE, "density_kg_m3": 2700.0}, friction)
    expected = tp.factor_of_safety(SYSTEM, np.radians([36.0, 40.0]), support=SUPPORT, unit_weight=26.487e3)
    np.testing.assert_allclose(dense, expected, rtol=1e-12)
    default = _fs(BASE, friction)
    np.testing.assert_allclose(
        default, tp.factor_of_safety(SYSTEM, np.radians([36.0, 40.0]), support=SUPPORT, unit_weight=26e3)
    )
    assert not np.allclose(dense, default, rtol=1e-6)
    with pytest.raises(ValueError, match="not both"):
        Toppling(**BASE, density_kg_m3=2700.0, unit_weight_kN_m3=26.0)


def test_separate_side_friction_and_water_per_sample():
    """Each sample's FS is the function's, with the water of a 20 m level."""
    base = {**BASE, "side_friction_deg": 30.0, "water_level_m": 20.0, "density_kg_m3": 2500.0}
    inputs = {"friction_deg": [38.0, 42.0], "side_friction_deg": [30.0, 35.0]}
    water = tp.phreatic_water(SYSTEM, [-1e9, 1e9], [20.0, 20.0])
    expected = tp.factor_of_safety(
        SYSTEM, np.radians([38.0, 42.0]), np.radians([30.0, 35.0]), SUPPORT, 2500 * 9.81, water
    )
    np.testing.assert_allclose(_fs(base, inputs), expected, rtol=1e-12)


def test_a_batch_with_one_geometry_is_one_vectorised_call(monkeypatch):
    """A dry study's batch of 1,000 samples of base and side friction builds one system and calls the
    FS once (a nan standing for "dry" made every row unique: one call per sample, 170 s for 10^4)."""
    from bbmc.sweep import models

    calls = []
    original = models.toppling.factor_of_safety

    def counted(*args, **kwargs):
        calls.append(1)
        return original(*args, **kwargs)

    monkeypatch.setattr(models.toppling, "factor_of_safety", counted)
    rng = np.random.default_rng(1)
    inputs = {"friction_deg": rng.normal(40, 3, 1000), "side_friction_deg": rng.normal(35, 3, 1000)}
    fs = _fs({**BASE, "side_friction_deg": 35.0, "support": None}, inputs)
    assert len(calls) == 1 and np.isfinite(fs).all()


def test_a_support_placed_by_its_level_on_the_face():
    """support.level_m: 2 m above the toe, horizontal (angle_deg = the base dip): the toe block, 2.309 m
    up its face, as `toppling.face_support` places it."""
    base = {**BASE, "support": {"force_kN_per_m": 2000.0, "angle_deg": 30.0, "level_m": 2.0}}
    placed = tp.face_support(SYSTEM, 2.0, 2e6, 0.0)
    assert placed.height[0] == pytest.approx(2.0 / math.cos(math.radians(30.0)), rel=1e-12)
    expected = tp.factor_of_safety(SYSTEM, np.radians([38.0]), support=placed, unit_weight=26e3)
    np.testing.assert_allclose(_fs(base, {"friction_deg": [38.0]}), expected, rtol=1e-12)
