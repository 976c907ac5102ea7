"""Kinematic analysis: each limit of each mode, with poles or lines 0.01 deg inside and outside it
(the tolerance: far above round-off, far below any reading's precision); a hand-worked wedge; the
criteria of Rocscience Dips' help pages ("Planar Sliding", "Wedge Sliding", "Flexural Toppling",
"Direct Toppling"), Hudson & Harrison 1997 ch. 18 and Goodman 1980 sec. 8.4, as named per test."""

from __future__ import annotations

import numpy as np
import pytest

from bbmc.geometry.orientation import apparent_dip, line_vectors, poles
from bbmc.kinematics.criteria import (
    base_planes,
    direct_toppling,
    flexural_toppling,
    planar_sliding,
    wedge_sliding,
)
from bbmc.kinematics.face import Face, KinematicLimits
from bbmc.kinematics.modes import LINE_MODES, POLE_MODES, critical_zone_masks

r = np.radians
EPS = 0.01  # deg either side of a limit
FACE = Face(r(60.0), r(90.0))  # a face of 60/090
PHI = r(30.0)
LIMITS = KinematicLimits()


def plane(dip_deg: float, dip_direction_deg: float) -> np.ndarray:
    return poles(r(np.array([dip_deg])), r(np.array([dip_direction_deg])))


def line(trend_deg: float, plunge_deg: float) -> np.ndarray:
    return line_vectors(r(np.array([trend_deg])), r(np.array([plunge_deg]))).reshape(1, 3)


def face_apparent_dip_deg(dip_deg: float, dip_direction_deg: float, trend_deg: float) -> float:
    return float(np.degrees(apparent_dip(r(dip_deg), r(dip_direction_deg), r(trend_deg))))


# --- planar sliding: Dips "Planar Sliding"; Hudson & Harrison 1997 sec. 18.3 -----------------------


def test_planar_daylight_envelope_is_the_face_apparent_dip_along_the_plane_dip_direction():
    """Dips: the pole inside the daylight envelope; the plane's dip below the face's apparent dip
    along the plane's dip direction (59.62 deg along 100 deg for the face 60/090)."""
    limit = face_apparent_dip_deg(60.0, 90.0, 100.0)
    assert limit == pytest.approx(np.degrees(np.arctan(np.tan(r(60)) * np.cos(r(10)))), abs=1e-12)
    assert planar_sliding(plane(limit - EPS, 100.0), FACE, PHI, LIMITS)[0]
    assert not planar_sliding(plane(limit + EPS, 100.0), FACE, PHI, LIMITS)[0]


def test_planar_friction_cone():
    """Dips: the pole outside the friction cone, dip > phi."""
    assert planar_sliding(plane(30.0 + EPS, 90.0), FACE, PHI, LIMITS)[0]
    assert not planar_sliding(plane(30.0 - EPS, 90.0), FACE, PHI, LIMITS)[0]


@pytest.mark.parametrize("side", [-1.0, 1.0])
def test_planar_lateral_limits_default_20_deg(side):
    """Dips: straight lateral limits, +/-20 deg of the face's dip direction by default."""
    assert planar_sliding(plane(40.0, 90.0 + side * (20.0 - EPS)), FACE, PHI, LIMITS)[0]
    assert not planar_sliding(plane(40.0, 90.0 + side * (20.0 + EPS)), FACE, PHI, LIMITS)[0]
    wide = KinematicLimits(planar=r(30.0))
    assert planar_sliding(plane(40.0, 90.0 + side * 25.0), FACE, PHI, wide)[0]


def test_planar_dipping_into_the_slope_never_slides():
    assert not planar_sliding(plane(40.0, 270.0), FACE, PHI, LIMITS)[0]


# --- wedge sliding: Dips "Wedge Sliding"; Hudson & Harrison 1997 sec. 18.4 -------------------------


def test_wedge_primary_zone_friction_cone():
    """Dips: primary zone, the line plunging more than phi..."""
    assert wedge_sliding(line(90.0, 30.0 + EPS), FACE, PHI).primary[0]
    assert not wedge_sliding(line(90.0, 30.0 - EPS), FACE, PHI).primary[0]


def test_wedge_primary_zone_daylight():
    """... and less than the face's apparent dip along its trend (inside the face's great circle)."""
    limit = face_apparent_dip_deg(60.0, 90.0, 130.0)
    assert wedge_sliding(line(130.0, limit - EPS), FACE, PHI).primary[0]
    assert not wedge_sliding(line(130.0, limit + EPS), FACE, PHI).primary[0]


def test_wedge_secondary_zone_between_friction_cone_face_and_friction_plane():
    """Dips' secondary zone (sliding on one plane): plunge <= phi, daylighting, and at or below the
    great circle of the plane dipping phi towards the face's dip direction (mplstereonet's reading
    of Dips). Along 150 deg that plane's apparent dip is atan(tan 30 cos 60) = 16.10 deg."""
    floor = face_apparent_dip_deg(30.0, 90.0, 150.0)
    assert floor == pytest.approx(np.degrees(np.arctan(np.tan(r(30)) * 0.5)), abs=1e-12)
    assert wedge_sliding(line(150.0, floor + EPS), FACE, PHI).secondary[0]
    assert not wedge_sliding(line(150.0, floor - EPS), FACE, PHI).secondary[0]
    assert wedge_sliding(line(150.0, 30.0 - EPS), FACE, PHI).secondary[0]
    steeper = wedge_sliding(line(150.0, 30.0 + EPS), FACE, PHI)
    assert steeper.primary[0] and not steeper.secondary[0]


def test_wedge_worked_example_hand_worked():
    """Hand-worked: planes 50/060 and 50/120 meet in the line 090 / atan(tan 50 cos 30)
    (tan 50 = 1.19175, x cos 30 = 1.03209, atan = 45.905 deg; Priest 1993 eq. 2.6, the apparent dip of
    either plane along 090), which plunges more than
    phi = 30 and less than the 60 deg face: primary zone. The face at 45: it no longer daylights."""
    normals = np.vstack([plane(50.0, 60.0), plane(50.0, 120.0)])
    lines = np.cross(normals[0], normals[1]).reshape(1, 3)
    lines /= np.linalg.norm(lines)
    lines = -lines if lines[0, 2] > 0 else lines
    plunge = np.degrees(np.arcsin(-lines[0, 2]))
    assert plunge == pytest.approx(45.905, abs=0.001)
    assert np.degrees(np.arctan2(lines[0, 0], lines[0, 1])) % 360 == pytest.approx(90.0, abs=1e-9)
    assert wedge_sliding(lines, FACE, PHI).primary[0]
    assert not wedge_sliding(lines, Face(r(45.0), r(90.0)), PHI).primary[0]


# --- flexural toppling: Goodman 1980 sec. 8.4; Dips "Flexural Toppling" -----------------------------


def test_flexural_slip_limit_in_the_face_opposite_direction_is_goodmans():
    """Goodman: planes dipping into the face with dip >= 90 - psi_f + phi = 60 deg here."""
    assert flexural_toppling(plane(60.0 + EPS, 270.0), FACE, PHI, LIMITS)[0]
    assert not flexural_toppling(plane(60.0 - EPS, 270.0), FACE, PHI, LIMITS)[0]


def test_flexural_slip_limit_off_axis_is_dips_great_circle():
    """Dips: the pole outside the slip-limit plane (dip psi_f - phi = 30, towards the face's dip
    direction). 25 deg off axis the pole must plunge less than atan(tan 30 cos 25) = 27.62 deg, so
    the plane must dip more than 62.38 deg: stricter than the issue's dip >= 60 deg."""
    pole_limit = face_apparent_dip_deg(30.0, 90.0, 115.0)
    dip_limit = 90.0 - pole_limit
    assert dip_limit == pytest.approx(62.38, abs=0.005)
    assert flexural_toppling(plane(dip_limit + EPS, 295.0), FACE, PHI, LIMITS)[0]
    assert not flexural_toppling(plane(dip_limit - EPS, 295.0), FACE, PHI, LIMITS)[0]


@pytest.mark.parametrize("side", [-1.0, 1.0])
def test_flexural_lateral_limits_default_30_deg(side):
    """Dips (and the issue): +/-30 deg of the face's opposite direction by default."""
    assert flexural_toppling(plane(85.0, 270.0 + side * (30.0 - EPS)), FACE, PHI, LIMITS)[0]
    assert not flexural_toppling(plane(85.0, 270.0 + side * (30.0 + EPS)), FACE, PHI, LIMITS)[0]


def test_flexural_needs_a_face_steeper_than_friction():
    assert not flexural_toppling(plane(89.0, 270.0), Face(r(30.0), r(90.0)), r(35.0), LIMITS)[0]


def test_a_vertical_plane_topples_whichever_sense_its_pole_was_given():
    """A vertical plane's pole is one point of the primitive circle, either sense."""
    vertical = plane(90.0, 270.0)
    assert flexural_toppling(vertical, FACE, PHI, LIMITS)[0]
    assert flexural_toppling(-vertical, FACE, PHI, LIMITS)[0]


# --- direct toppling: Dips "Direct Toppling"; Hudson & Harrison 1997 sec. 18.5 ---------------------

STEEP_FACE = Face(r(70.0), r(90.0))  # zones 1+2 from plunge 20 deg, zone 2 from 60 deg (phi 30)


def zones(trend, plunge):
    z = direct_toppling(line(trend, plunge), STEEP_FACE, PHI, LIMITS)
    return int(z.zone_1[0]) * 1 + int(z.zone_2[0]) * 2 + int(z.zone_3[0]) * 3


def test_direct_toppling_slope_angle_circle():
    """Dips: intersections into the slope plunging at least 90 - psi_f (the circle of cone angle
    psi_f): zone 1 from 20 deg for a 70 deg face."""
    assert zones(270.0, 20.0 + EPS) == 1
    assert zones(270.0, 20.0 - EPS) == 0


def test_direct_toppling_zones_split_by_the_base_planes_friction_cone():
    """Dips: the boundary of zones 1 and 2 is the friction cone of the base planes, 90 - phi."""
    assert zones(270.0, 60.0 + EPS) == 2
    assert zones(270.0, 60.0 - EPS) == 1


@pytest.mark.parametrize("side", [-1.0, 1.0])
def test_direct_toppling_lateral_limits(side):
    """Dips: straight lateral limits about the slope dip direction (here about its opposite, the
    intersections dipping into the slope), +/-20 deg by default."""
    assert zones(270.0 + side * (20.0 - EPS), 40.0) == 1
    assert zones(270.0 + side * (20.0 + EPS), 40.0) == 0


@pytest.mark.parametrize("side", [-1.0, 1.0])
def test_oblique_toppling_zone_3(side):
    """Dips: zone 3 (oblique toppling), inside the friction cone and outside the lateral limits, on
    the into-slope side of the strike (read from Dips' figure)."""
    assert zones(270.0 + side * 45.0, 60.0 + EPS) == 3
    assert zones(270.0 + side * 45.0, 60.0 - EPS) == 0
    assert zones(270.0 + side * (90.0 - EPS), 65.0) == 3
    assert zones(270.0 + side * (90.0 + EPS), 65.0) == 0


def test_base_planes_sliding_and_release():
    """Dips: a base plane's pole in zone 1 (dip between phi and psi_f, out of the face) can slide as
    the blocks topple; in zone 2 (dip below phi) it only releases them."""
    planes = np.vstack([plane(35.0, 90.0), plane(25.0, 90.0), plane(70.0 + EPS, 90.0), plane(25.0, 150.0)])
    zone = base_planes(planes, STEEP_FACE, PHI, LIMITS)
    assert list(zone.zone_1) == [True, False, False, False]
    assert list(zone.zone_2) == [False, True, False, False]
    assert list(zone.zone_3) == [False, False, False, True]


# --- the zones on the net are the classification ------------------------------------------------


def test_critical_zone_masks_read_lower_hemisphere_points_as_poles_and_as_lines():
    """The stereonet's masks take lower-hemisphere points and read each as a pole (of a plane) or as a
    line, by hand for the 60/090 face and phi 30: the point trend 270 plunge 50 is the pole of the plane
    40/090 (dips out of the face at 40 > 30 deg, daylights, on the face's dip direction: planar
    sliding); the point trend 270 plunge 20 is the pole of 70/090 (dips steeper than the face: no
    sliding); the point trend 090 plunge 40, read as a line, plunges 40 > 30 deg out of the face below
    its 60 deg dip (a sliding wedge's line); the point trend 090 plunge 5 is a line, trending into the
    face, of a plane dipping 85/270 when read as a pole: flexural toppling (85 >= 90 - 60 + 30)."""
    points = np.vstack([line(270.0, 50.0), line(270.0, 20.0), line(90.0, 40.0), line(90.0, 5.0)])
    masks = critical_zone_masks(points, FACE, PHI)
    assert set(masks) == set(POLE_MODES + LINE_MODES)
    np.testing.assert_array_equal(masks["planar_sliding"], [True, False, False, False])
    np.testing.assert_array_equal(masks["wedge_sliding"], [False, False, True, False])
    np.testing.assert_array_equal(masks["flexural_toppling"], [False, False, False, True])


def test_flexural_slip_limit_counts_a_plane_on_it():
    """Goodman's dip >= 90 - psi_f + phi: a plane at exactly 60 deg into the 60/090 face topples at
    phi 30 (readings in whole degrees sit on limits)."""
    assert flexural_toppling(plane(60.0, 270.0), FACE, PHI, LIMITS)[0]


def test_friction_per_reading():
    """A friction angle per reading: each plane tested against its own."""
    normals = np.vstack([plane(40.0, 90.0), plane(40.0, 90.0)])
    got = planar_sliding(normals, FACE, r(np.array([35.0, 45.0])), LIMITS)
    assert list(got) == [True, False]
