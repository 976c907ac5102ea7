"""bbmc.outputs.wedge_figures and wedge_vtk on Hoek & Bray's classic wedge (issue 35): the figures are
written; the VTK file read back has the wedge's vertices, face ids, areas and volume (by the divergence
theorem over its triangles), with and without a tension crack; the tables of the figures' numbers."""

from __future__ import annotations

import meshio
import numpy as np
import pytest

from bbmc.outputs.wedge_figure_tables import force_table, vertex_table
from bbmc.outputs.wedge_figures import (
    wedge_figure,
    wedge_net_figure,
)
from bbmc.outputs.wedge_vtk import enclosed_volume, one_wedge, wedge_triangles, write_wedge_vtu
from bbmc.slope.wedge.analysis import WedgeOrientations, analyse_wedges
from bbmc.slope.wedge.geometry import TensionCrack, WedgeNotFormedError
from bbmc.slope.wedge.loads import force_vector
from bbmc.slope.wedge.mechanics import MohrCoulomb
from bbmc.slope.wedge.support import Bolt, support_resultants
from bbmc.slope.wedge.water import HoekBrayWater

R = np.radians
FT, PSF, PCF = 0.3048, 47.880259, 157.087464  # m, Pa, N/m^3 per ft, psf, pcf
CLASSIC = WedgeOrientations(R(45), R(105), R(70), R(235), R(65), R(185), R(12), R(195))
STRENGTH = (MohrCoulomb(500 * PSF, R(20)), MohrCoulomb(1000 * PSF, R(30)))
LOADS = {"unit_weight": 160 * PCF, "water_unit_weight": 62.5 * PCF, "height_h1": 100 * FT}
CRACK = TensionCrack(R(70), R(165), 40 * FT)


def _classic(**kwargs):
    return analyse_wedges(CLASSIC, *STRENGTH, water=HoekBrayWater(), **LOADS, **kwargs)


@pytest.mark.parametrize("crack", [None, CRACK], ids=["tetrahedron", "crack"])
def test_vtu_round_trip(tmp_path, crack):
    """The .vtu read back (meshio) holds the wedge's vertices (to 1e-12 relative: binary float64), a
    closed surface whose volume by the divergence theorem and whose areas per face_id equal the
    geometry's to 1e-9 relative, outward normals, and face ids 1-4 (and 5 for the crack)."""
    analysis = _classic(crack=crack)
    g = analysis.geometry
    mesh = meshio.read(write_wedge_vtu(tmp_path / "wedge.vtu", g))
    np.testing.assert_allclose(mesh.points, g.vertices, rtol=1e-12, atol=1e-12 * float(g.height_h))
    triangles = mesh.cells_dict["triangle"]
    ids, areas, normals = (mesh.cell_data[k][0] for k in ("face_id", "area_m2", "normal"))
    assert enclosed_volume(mesh.points, triangles) == pytest.approx(float(g.volume), rel=1e-9)
    expected = {1: g.area_1, 2: g.area_2, 3: g.area_face, 4: g.area_upper, 5: g.area_crack}
    assert set(ids.tolist()) == ({1, 2, 3, 4, 5} if crack else {1, 2, 3, 4})
    for face_id in set(ids.tolist()):
        assert areas[ids == face_id].sum() == pytest.approx(float(expected[face_id]), rel=1e-9)
    outward = np.einsum("ij,ij->i", normals, mesh.points[triangles].mean(axis=1) - mesh.points.mean(axis=0))
    assert np.all(outward > 0.0)
    np.testing.assert_allclose(normals[ids == 1][0], -g.normal_1, atol=1e-9)  # normal_1 points inward


def test_figures_are_written(tmp_path):
    """The 3D figure (with a crack and a bolt) and the net are written as PNGs."""
    bolt = Bolt(force=1.0e6, trend=R(15), plunge=R(10), count=20)
    active, _ = support_resultants([bolt])
    analysis = _classic(crack=CRACK, forces=active)
    figures = {
        "wedge.png": wedge_figure(analysis, bolts=[bolt], title="classic"),
        "net.png": wedge_net_figure(analysis, CLASSIC, {"plane 1": R(20), "plane 2": R(30)}),
    }
    for name, figure in figures.items():
        figure.savefig(tmp_path / name)
        assert (tmp_path / name).stat().st_size > 10_000


def test_wedge_that_does_not_form_is_refused(tmp_path):
    """A batch whose second wedge cannot form (plane 1 dipping into the slope): the figure and the VTK
    file of that wedge raise WedgeNotFormedError, the first is drawn."""
    both = WedgeOrientations(R(45), R([105, 5]), *CLASSIC.angles()[2:])
    analysis = analyse_wedges(both, *STRENGTH, **LOADS)
    assert not bool(analysis.geometry.formed[1])
    with pytest.raises(WedgeNotFormedError):
        write_wedge_vtu(tmp_path / "no.vtu", analysis.geometry, index=(1,))
    with pytest.raises(WedgeNotFormedError):
        wedge_figure(analysis, index=(1,))
    write_wedge_vtu(tmp_path / "yes.vtu", analysis.geometry, index=(0,))


def test_tables_hold_the_figures_numbers():
    """The vertex table is the geometry's vertices; each force's size, trend and plunge rebuild its
    components through `loads.force_vector` (to 1e-9 relative; upward forces have negative plunge);
    the FS bins count every finite FS once."""
    bolt = Bolt(force=1.0e6, trend=R(15), plunge=R(10), count=20)
    active, _ = support_resultants([bolt])
    analysis = _classic(crack=CRACK, forces=active)
    vertices = vertex_table(analysis.geometry)
    assert vertices["vertex"].tolist() == ["O", "C1", "C2", "P", "Q", "R"]
    np.testing.assert_allclose(vertices[["east_m", "north_m", "up_m"]], analysis.geometry.vertices)
    forces = force_table(analysis, bolts=[bolt])
    assert forces["symbol"].tolist() == ["W", "U1", "U2", "V", "B1", "F"]
    rebuilt = force_vector(forces["size_kN"], R(forces["trend_deg"]), R(forces["plunge_deg"]))
    np.testing.assert_allclose(rebuilt, forces[["east_kN", "north_kN", "up_kN"]], rtol=1e-9, atol=1e-9)
    assert (forces.set_index("symbol").loc[["U1", "U2"], "plunge_deg"] < 0.0).all()
    np.testing.assert_allclose(
        forces.set_index("symbol").loc["B1", ["trend_deg", "plunge_deg"]], [15.0, 10.0]
    )


@pytest.mark.parametrize("with_crack", [False, True], ids=["tetrahedron", "crack"])
def test_triangles_close_every_random_wedge(with_crack):
    """Over 400 random wedges (planes, face, upper surface and a crack drawn uniformly), every one that
    forms has outward triangles whose divergence-theorem volume and areas per face equal the geometry's
    to 1e-9 relative (the law holds over the whole range, not for the classic wedge alone)."""
    rng = np.random.default_rng(35)
    n = 400
    dips = R(rng.uniform([10, 10, 50, 0], [85, 85, 89, 20], (n, 4)))
    directions = R(rng.uniform(0, 360, (n, 4)))
    directions[:, 2:] = R(180.0) + R(rng.uniform(-20, 20, (n, 2)))  # face and upper surface face south
    crack = TensionCrack(R(rng.uniform(50, 89, n)), R(rng.uniform(150, 210, n)), rng.uniform(1, 30, n))
    g = analyse_wedges(
        WedgeOrientations(*np.column_stack([dips, directions])[:, [0, 4, 1, 5, 2, 6, 3, 7]].T),
        *STRENGTH,
        unit_weight=26e3,
        height_h=50.0,
        crack=crack if with_crack else None,
    ).geometry
    formed = np.flatnonzero(g.formed)
    assert len(formed) > 20
    for k in formed:
        points, triangles, ids = wedge_triangles(one_wedge(g, (k,)))
        assert enclosed_volume(points, triangles) == pytest.approx(float(g.volume[k]), rel=1e-9)
        a, b, c = (points[triangles[:, j]] for j in range(3))
        areas = np.linalg.norm(np.cross(b - a, c - a), axis=1) / 2.0
        expected = {1: g.area_1, 2: g.area_2, 3: g.area_face, 4: g.area_upper, 5: g.area_crack}
        assert set(ids.tolist()) == set(range(1, 6 if with_crack else 5))
        for face_id in set(ids.tolist()):
            area = expected[face_id]
            assert areas[ids == face_id].sum() == pytest.approx(float(area[k]), rel=1e-9)
