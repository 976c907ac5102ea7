"""Issue 36's wedges: the 3D engine's strength-reduction factor of safety (`bbmc.fos.
strength_reduction3d`) against the limit equilibrium's (`bbmc.slope.wedge.analysis`), dry, on a wedge
10 m high (H1) of density 2500 kg/m3 resting on the held rock of its two planes
(`bbmc.slope.wedge.engine_scene`), dry or under equal uniform water pressures on both planes (the
engine's joint type's given `pressure` on the closed parts of its contacts, limit equilibrium's
`PlanePressures`). The search bisects to a bracket 0.001 wide (0.08 % of these FS), so the 1 %
tolerance is the issue's, not the search's. Every FS measured is in the test's docstring."""

import math

import pytest

from bbmc.dem3d.joint_laws import MohrCoulomb
from bbmc.fos.strength_reduction3d import factor_of_safety_3d
from bbmc.scene.fos_settings import StrengthReduction
from bbmc.slope.wedge.analysis import WedgeOrientations, analyse_wedges
from bbmc.slope.wedge.engine_scene import wedge_scene
from bbmc.slope.wedge.geometry import wedge_geometries
from bbmc.slope.wedge.mechanics import MohrCoulomb as LimitMohrCoulomb
from bbmc.slope.wedge.mechanics import SlidingMode
from bbmc.slope.wedge.water import PlanePressures

RHO, G, H1 = 2500.0, 9.81, 10.0
KN = 1e9  # Pa/m: the wedge's closure under its weight is ~0.1 mm, the drawn geometry stays
SEARCH = StrengthReduction(tolerance=1e-3)


def orientations(planes, face=(70.0, 175.0)):
    """Planes 1 and 2, the face (dip, dip direction) [deg]; the upper surface horizontal."""
    (d1, a1), (d2, a2) = planes
    angles = (d1, a1, d2, a2, *face, 0.0, face[1])
    return WedgeOrientations(*(math.radians(a) for a in angles))


def limit_equilibrium(wedge, cohesion, phi_deg, pressure=0.0):
    """LE's FS and mode, both planes of c [Pa], phi [deg], each under the given mean `pressure` [Pa]."""
    strength = LimitMohrCoulomb(cohesion, math.radians(phi_deg))
    water = PlanePressures(pressure, pressure)
    result = analyse_wedges(wedge, strength, strength, unit_weight=RHO * G, height_h1=H1, water=water)
    return float(result.factor_of_safety), SlidingMode(int(result.solution.mode))


def engine_fs(wedge, cohesion, phi_deg, refine=1, pressure=0.0):
    """The engine's SRM FS, both planes of c [Pa], phi [deg] and the given uniform `pressure` [Pa]."""
    geometry = wedge_geometries(*wedge.angles(), height_h1=H1)
    law = MohrCoulomb(KN, KN / 2, math.radians(phi_deg), cohesion, pressure=pressure)
    result = factor_of_safety_3d(wedge_scene(geometry, RHO, law, refine=refine), SEARCH)
    assert result.bracketed
    return result.factor_of_safety


THREE_DEC = orientations(((40.0, 130.0), (60.0, 220.0)))
LIFTING = orientations(((40.0, 170.0), (80.0, 250.0)))  # plane 1's dip nearly along plane 2
LIFTING_OFF = orientations(((40.0, 180.0), (65.0, 270.0)))  # plane 1's dip points away from plane 2


def test_three_dec_wedge_slides_on_both_planes_at_the_limit_equilibrium_fs():
    """3DEC's sliding wedge (planes 40/130 and 60/220, c = 0, phi 40 deg; face 70/175, horizontal upper
    surface, so it daylights): limit equilibrium 1.2746, as 3DEC's; the engine within 1 % (measured
    1.2799 at a 1e-4 bracket, +0.41 %, in about 2 s after compiling; above LE by the wedging the trial's
    slip leaves: the cross shear on plane 1 ends pushing the wedge into the V, N1 + N2 0.920 W against
    LE's 0.915 W)."""
    fs, mode = limit_equilibrium(THREE_DEC, 0.0, 40.0)
    assert mode == SlidingMode.BOTH
    assert fs == pytest.approx(1.2746, abs=1e-4)
    assert engine_fs(THREE_DEC, 0.0, 40.0) == pytest.approx(fs, rel=0.01)


def test_wedge_sliding_on_one_plane_with_the_other_lifted_off():
    """Planes 40/180 and 65/270, phi 47 deg: the wedge leaves plane 2 (sliding down plane 1's dip moves
    it off plane 2 at dip . n2 = -0.27) and slides on plane 1 alone, FS = tan(phi) / tan(40 deg) = 1.278
    by limit equilibrium; the engine within 1 % (measured 1.2778, -0.01 %)."""
    fs, mode = limit_equilibrium(LIFTING_OFF, 0.0, 47.0)
    assert mode == SlidingMode.PLANE_1
    assert fs == pytest.approx(math.tan(math.radians(47.0)) / math.tan(math.radians(40.0)), rel=1e-9)
    assert engine_fs(LIFTING_OFF, 0.0, 47.0) == pytest.approx(fs, rel=0.01)


@pytest.mark.xfail(strict=True, reason="measured +1.15 % (1.2927); converged (refinement 3) +1.06 %")
def test_wedge_barely_lifting_off_plane_2():
    """A known limit. Planes 40/170 and 80/250, phi 47 deg: the wedge leaves plane 2 and slides down plane 1's
    dip, FS = tan(phi) / tan(40 deg) = 1.278 by limit equilibrium; the engine within 1 %: not met, measured
    1.2927 (+1.15 %) at a 1e-4 bracket; 1.2942, 1.2927, 1.2921, 1.2915 at refinement 0..3, 1.2882 to 1.2946
    over half the step and damping 0.5 to 0.95. Its earlier 1.2808 (+0.22 %) was refinement 1's artefact: a
    share's shear force jumped from its centroid to its centre of pressure as it slipped, and the wedge
    shook at the limit (1.2880, 1.2810, 1.2910, 1.2914, 1.2914 at refinement 0..4 then, 1.2646 to 1.3452
    over the step and damping). The vertical through the centroid meets plane 1 inside the wedge's face
    (barycentric 0.43, 0.25, 0.33), so it cannot topple. It was 1.2100 (-5.3 %) while the trend called a
    trial that had moved 2e-6 m of its 7 m failure displacement "projected": a resting run (r >= 1) projects
    an infinite remainder (`bbmc.dem.verdict`, fixed). Plane 2 still carries 1.4 % of the normal force: the
    wedge's settlement on plane 1 (along -n1, n1 . n2 = 0.24) closes plane 2, which sliding down the dip
    opens only slowly (dip . n2 = 0.019); its friction is why the engine is above LE (mu N2 / T ~ 1.4 %),
    and what the engine still lacks to meet LE here."""
    fs, mode = limit_equilibrium(LIFTING, 0.0, 47.0)
    assert mode == SlidingMode.PLANE_1
    assert fs == pytest.approx(math.tan(math.radians(47.0)) / math.tan(math.radians(40.0)), rel=1e-9)
    assert engine_fs(LIFTING, 0.0, 47.0) == pytest.approx(fs, rel=0.01)


def test_wedge_with_cohesion():
    """3DEC's wedge with c = 10 kPa, phi 30 deg on both planes: limit equilibrium 1.3156 (the cohesion
    counted as LE counts it, c A / F, ``after_slip keep``); the engine within 1 %
    (measured 1.3194 at a 1e-4 bracket, +0.29 %)."""
    fs, mode = limit_equilibrium(THREE_DEC, 10e3, 30.0)
    assert mode == SlidingMode.BOTH
    assert engine_fs(THREE_DEC, 10e3, 30.0) == pytest.approx(fs, rel=0.01)


PRESSURE = 5e3  # Pa on both planes: about an eighth of the wedges' mean normal stress, W / (A1 + A2)


@pytest.mark.parametrize(
    "wedge, cohesion, phi_deg, mode, dry, wet",
    [
        (THREE_DEC, 0.0, 40.0, SlidingMode.BOTH, 1.2746, 1.0906),
        (LIFTING_OFF, 0.0, 47.0, SlidingMode.PLANE_1, 1.2780, 1.0765),
        (THREE_DEC, 10e3, 30.0, SlidingMode.BOTH, 1.3156, 1.1890),
    ],
    ids=["both-planes", "one-plane-lifted-off", "with-cohesion"],
)
def test_wedges_under_equal_uniform_pressures(wedge, cohesion, phi_deg, mode, dry, wet):
    """The three wedges above with 5 kPa on both planes (the engine's p A on each plane's closed part,
    LE's U_i = p A_i): LE's FS falls from the dry one by 10 to 15 % (its mode kept), the engine within
    1 % of it. Measured (engine, LE, error): both planes 1.0923, 1.0906, +0.15 %; one plane lifted off
    1.0864, 1.0853, +0.11 % (LE puts U_2 on plane 2, which the wedge leaves, the engine only on what
    stays closed of it; U_2 is 0.2 MN beside the wedge's 32 MN weight); with cohesion 1.1890, 1.1890,
    -0.004 %. 1.5 to 4.5 s each."""
    assert limit_equilibrium(wedge, cohesion, phi_deg)[0] == pytest.approx(dry, abs=1e-4)
    fs, found = limit_equilibrium(wedge, cohesion, phi_deg, PRESSURE)
    assert found == mode
    assert fs == pytest.approx(wet, abs=1e-4)
    assert engine_fs(wedge, cohesion, phi_deg, pressure=PRESSURE) == pytest.approx(fs, rel=0.01)


def test_wedge_fs_does_not_depend_on_the_refinement():
    """3DEC's wedge at refinement 0, 1, 2 (1, 4 and 16 sub-contacts on each wedge face): each within 1 %
    of limit equilibrium, spread <= 0.5 % (the issue's). Measured with a bracket of 1e-4 (so not the
    bisection's): 1.2779, 1.2799, 1.2813 (refinement 3: 1.2813), spread 0.27 %; the cohesive wedge
    1.3183, 1.3194, 1.3188, 1.3194 (0.08 %), the lift-off wedge 1.2942, 1.2927, 1.2921, 1.2915 (0.17 %).
    It was 0.60 % to 0.8 % (1.2705, 1.2774, 1.2802, 1.2810, 1.2813 at refinement 0..4) while a share's
    shear force jumped from its centroid to its centre of pressure as it slipped (`bbmc.dem3d.
    contact_forces`): a coarse share near its limit shook the wedge and let it slip early. About 4 s."""
    found = [engine_fs(THREE_DEC, 0.0, 40.0, refine) for refine in (0, 1, 2)]
    fs, _ = limit_equilibrium(THREE_DEC, 0.0, 40.0)
    for value in found:
        assert value == pytest.approx(fs, rel=0.01)
    assert max(found) - min(found) <= 5e-3 * fs


def test_wedge_fs_does_not_move_with_the_search_margin_or_the_step_budget():
    """3DEC's wedge (refinement 0, a 0.01 bracket): the broad phase's margin x 4 or / 4 and the trials'
    step budget x 2 give the same bracket, bit for bit (measured, also at a 1e-3 bracket: 1.27295 in
    each): the trend decides a trial before its budget, and a search carries every pair's state."""
    geometry = wedge_geometries(*THREE_DEC.angles(), height_h1=H1)
    law = MohrCoulomb(KN, KN / 2, math.radians(40.0), 0.0)
    coarse = StrengthReduction(tolerance=1e-2)
    longer = StrengthReduction(tolerance=1e-2, response_multiple=20.0, min_trial_steps=4000)
    found = []
    for scale, settings in ((1.0, coarse), (4.0, coarse), (0.25, coarse), (1.0, longer)):
        model = wedge_scene(geometry, RHO, law, refine=0)
        model.margin *= scale
        found.append(factor_of_safety_3d(model, settings).bracket)
    assert all(bracket == found[0] for bracket in found)
