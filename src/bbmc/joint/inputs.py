"""The full Barton-Bandis joint as a config gives it, and the checks that keep its derived inputs
(`bbmc.joint.derived`) meaningful: one place for the scene's law (`barton_bandis_mobilized`) and for
`bbmc joint`, and for the keys the scene's peak law (`barton_bandis`) shares with them. Units are in
the key names (MPa, m, deg); each check names its key.
"""

from __future__ import annotations

from typing import Annotated, ClassVar, Literal

from pydantic import Field, ValidationInfo, field_validator

from bbmc.config import Section

Angle = Annotated[float, Field(gt=0, lt=90)]
Positive = Annotated[float, Field(gt=0)]


def wall_not_stronger_than_rock(sigma_c_MPa: float, jcs0_MPa: float) -> None:
    """Refuse a rock weaker than its joint wall (sigma_c < JCS_0, where the aperture fit a_j would fall
    to its floor): ValueError naming both keys."""
    if sigma_c_MPa < jcs0_MPa:
        raise ValueError(
            f"sigma_c_MPa ({sigma_c_MPa}) is below jcs0_MPa ({jcs0_MPa}): a joint wall is not stronger "
            "than its rock"
        )


class ResidualAndScale(Section):
    """The keys a Barton-Bandis joint takes in both of its laws (the peak envelope and the full joint),
    with the same names, meaning and checks: phi_r, or the rebound ratio r/R it derives from (Barton &
    Choubey 1977), and the lab length L_0 of the joint's JRC and JCS and the field length L_n they are
    scaled to (Barton & Bandis 1982), computed by `bbmc.joint.derived.full_joint`. A law inherits this
    first and its own joint keys second, so that its `phi_b_deg` is read before these are checked
    against it; `residual_required`: one of phi_r_deg and rebound_ratio must be given."""

    residual_required: ClassVar[bool] = False

    phi_r_deg: Angle | None = None  # or from rebound_ratio
    rebound_ratio: Annotated[float, Field(ge=0, le=1)] | None = Field(default=None, validate_default=True)
    lab_length_m: Positive = 0.1  # L_0
    field_length_m: Positive | None = None  # L_n [default: lab_length_m, no scale effect]

    @field_validator("phi_r_deg")
    @classmethod
    def _residual_below_basic(cls, value: float | None, info: ValidationInfo) -> float | None:
        phi_b = info.data.get("phi_b_deg")
        if value is not None and phi_b is not None and value > phi_b:
            raise ValueError(f"exceeds phi_b_deg ({phi_b}): phi_r is at most the basic angle")
        return value

    @field_validator("rebound_ratio")
    @classmethod
    def _one_residual_source(cls, value: float | None, info: ValidationInfo) -> float | None:
        given = info.data.get("phi_r_deg") is not None
        how_many = "exactly one" if cls.residual_required else "at most one"
        if given and value is not None:
            raise ValueError(f"give {how_many} of phi_r_deg and rebound_ratio (both are given)")
        if cls.residual_required and not given and value is None:
            raise ValueError(f"give {how_many} of phi_r_deg and rebound_ratio (neither is given)")
        phi_b = info.data.get("phi_b_deg")
        if value is not None and phi_b is not None and phi_b - 20.0 * (1.0 - value) <= 0.0:
            raise ValueError(f"gives phi_r = phi_b_deg - 20 (1 - r/R) <= 0 with phi_b_deg {phi_b}")
        return value


class _LabJoint(Section):
    """The full joint's JRC_0 and JCS_0 at the lab length, and phi_b (before `ResidualAndScale`)."""

    jrc0: Annotated[float, Field(ge=0, le=20)]  # JRC_0 at the lab length
    jcs0_MPa: Positive  # JCS_0
    phi_b_deg: Angle


class FullJointInputs(ResidualAndScale, _LabJoint):
    """JRC_0 and JCS_0 at the lab length L_0, the field length L_n, phi_b, phi_r (or the rebound ratio
    r/R of Barton & Choubey 1977), the cap phi_max and the dilation's damage coefficient M."""

    residual_required: ClassVar[bool] = True

    phi_max_deg: Angle = Field(default=70.0, validate_default=True)
    damage: Literal["barton_1985"] | float = "barton_1985"  # M, or Barton et al. (1985)'s M(sigma_n)

    @field_validator("phi_max_deg")
    @classmethod
    def _cap_above_basic(cls, value: float, info: ValidationInfo) -> float:
        phi_b = info.data.get("phi_b_deg")
        if phi_b is not None and value <= phi_b:
            raise ValueError(f"must exceed phi_b_deg ({phi_b})")
        return value

    @field_validator("damage", mode="before")
    @classmethod
    def _damage(cls, value: object) -> object:
        number = isinstance(value, int | float) and not isinstance(value, bool)
        if value != "barton_1985" and not (number and 0 < value < float("inf")):
            raise ValueError("must be 'barton_1985' or a number M > 0")
        return float(value) if number else value
