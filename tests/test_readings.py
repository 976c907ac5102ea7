"""Reading a survey of orientation readings (bbmc.field.readings): each convention, quadrant bearings,
an Excel workbook, the declination, Terzaghi's weights on a scanline, a borehole and a mapped face, and
every bad input answered by one line naming the file, the row's line and the column.

Angles are compared to 1e-9 deg where they pass through sines and cosines only, and weights to 1e-9."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from bbmc.config import ConfigError
from bbmc.field.readings import SamplingFace, SamplingLine, read_readings
from bbmc.geometry.orientation import DIPS_MAX_WEIGHT, poles

CAP = 1.0 / np.sin(np.radians(15.0))


def _write(tmp_path: Path, text: str, name: str = "survey.csv") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _planes(readings) -> np.ndarray:
    return np.column_stack([np.degrees(readings.dip), np.degrees(readings.dip_direction)])


# ---------------------------------------------------------------------------------------------------
# conventions


def test_each_convention_gives_the_same_plane(tmp_path):
    """The plane 60/120 written four ways, one row each (a row's convention is the one its cells fill):
    dip/dip direction; strike 030 by the right-hand rule; its pole, trend 300 plunge 30; and a core
    reading in a vertical hole, bottom-of-core line at azimuth 180 (hole trend 000), alpha = 90 - 60 and
    beta = 120 - 180 + 360 = 300 (tests/test_orientation_algebra.py: dip direction = reference + beta)."""
    path = _write(tmp_path, (
        "dip_deg,dip_direction_deg,strike_deg,pole_trend_deg,pole_plunge_deg,alpha_deg,beta_deg,"
        "hole_trend_deg,hole_plunge_deg\n"
        "60,120,,,,,,,\n"
        "60,,30,,,,,,\n"
        ",,,300,30,,,,\n"
        ",,,,,30,300,0,90\n"
    ))  # fmt: skip
    readings = read_readings(path)
    assert list(readings.convention) == ["dip_direction", "strike_rhr", "pole", "core"]
    np.testing.assert_allclose(_planes(readings), [[60.0, 120.0]] * 4, atol=1e-9)
    np.testing.assert_allclose(readings.poles, np.tile(poles(*np.radians([60.0, 120.0])), (4, 1)), atol=1e-12)
    assert list(readings.lines) == [2, 3, 4, 5]


def test_core_readings_with_the_hole_given_once(tmp_path):
    """The hand-worked reading of tests/test_orientation_algebra.py: hole 180/60, bottom-of-core line,
    alpha 60, beta 90 gives 41.4096/049.1066; with the top-of-core line, beta 270 gives the same."""
    path = _write(tmp_path, "alpha_deg,beta_deg\n60,90\n")
    hole = SamplingLine(np.radians(180.0), np.radians(60.0))
    readings = read_readings(path, sampling=hole)
    np.testing.assert_allclose(_planes(readings), [[41.4096, 49.1066]], atol=1e-4)
    top_path = _write(tmp_path, "alpha_deg,beta_deg\n60,270\n", "top.csv")
    top = read_readings(top_path, sampling=hole, core_reference="top")
    np.testing.assert_allclose(top.poles, readings.poles, atol=1e-12)
    assert readings.terzaghi[0] == pytest.approx(
        1.0 / np.sin(np.radians(60.0)), abs=1e-9
    )  # |n.h| = sin alpha


def test_quadrant_bearings_and_a_forced_convention(tmp_path):
    """N30E = 030, S60E = 120, S10W = 190, N45W = 315; strike N30E (right-hand rule) dips to 120. With
    `convention`, the other conventions' columns are left alone (here, a strike column a tool derived)."""
    path = _write(tmp_path, "dip_deg,dip_direction_deg\n10,N30E\n20,S60E\n30,s10w\n40, N 45 W\n")
    np.testing.assert_allclose(np.degrees(read_readings(path).dip_direction), [30, 120, 190, 315], atol=1e-9)
    strike = _write(tmp_path, "strike_deg,dip_deg\nN30E,50\n", "strike.csv")
    assert np.degrees(read_readings(strike).dip_direction[0]) == pytest.approx(120.0)
    both = _write(tmp_path, "dip_deg,dip_direction_deg,strike_deg\n50,120,999\n", "both.csv")
    readings = read_readings(both, convention="dip_direction")
    np.testing.assert_allclose(_planes(readings), [[50.0, 120.0]], atol=1e-9)


def test_the_other_columns_are_kept(tmp_path):
    path = _write(tmp_path, (
        "# mapped 2024-05-02, compass 12 deg E\n"
        "dip_deg,dip_direction_deg,type,location,set,trace_length_m,position_m,weight,notes\n"
        "60,120,joint,bench 3,J1,2.5,0.4,2,open\n"
        "30,010,bedding,,,,,,\n"
    ))  # fmt: skip
    readings = read_readings(path)
    assert list(readings.kind) == ["joint", "bedding"]
    assert list(readings.location) == ["bench 3", ""]
    assert list(readings.set_label) == ["J1", ""]
    np.testing.assert_allclose(readings.trace_length, [2.5, np.nan])
    np.testing.assert_allclose(readings.position, [0.4, np.nan])
    np.testing.assert_allclose(readings.weights, [2.0, 1.0])  # no sampling geometry: Terzaghi 1
    assert list(readings.lines) == [3, 4]
    assert readings.count == 2
    assert readings.max_weight == DIPS_MAX_WEIGHT


def test_an_excel_workbook_reads_as_its_csv(tmp_path):
    table = pd.DataFrame(
        {"dip_deg": [60, 45.5], "dip_direction_deg": ["S60E", "S10W"], "type": ["joint", ""]}
    )
    table.to_excel(tmp_path / "survey.xlsx", index=False)
    table.to_csv(tmp_path / "survey.csv", index=False)
    sheet, text = read_readings(tmp_path / "survey.xlsx"), read_readings(tmp_path / "survey.csv")
    np.testing.assert_allclose(sheet.poles, text.poles, atol=1e-15)
    assert list(sheet.kind) == ["joint", ""]
    assert list(sheet.lines) == [2, 3]  # the spreadsheet's row numbers


# ---------------------------------------------------------------------------------------------------
# declination


def test_declination_turns_every_azimuth_true(tmp_path):
    """Declination 15 deg E: dip direction 350 -> 005, strike 350 -> dip direction 095, pole trend 350 ->
    plane dipping to 185; the scanline's trend too: magnetic 075 -> 090, so the plane 60/005 (true) meets
    it at |n . l| = sin 60 sin 5, capped."""
    path = _write(tmp_path, (
        "dip_deg,dip_direction_deg,strike_deg,pole_trend_deg,pole_plunge_deg\n"
        "60,350,,,\n"
        "60,,350,,\n"
        ",,,350,30\n"
    ))  # fmt: skip
    line = SamplingLine(np.radians(75.0), 0.0)
    readings = read_readings(path, declination=np.radians(15.0), sampling=line)
    np.testing.assert_allclose(np.degrees(readings.dip_direction), [5.0, 95.0, 185.0], atol=1e-9)
    expected = np.minimum(
        1.0 / np.abs(np.sin(np.radians(60.0)) * np.sin(np.radians([5.0, 95.0, 185.0]))), CAP
    )
    np.testing.assert_allclose(readings.terzaghi, expected, atol=1e-9)
    undeclined = read_readings(path, sampling=line)
    np.testing.assert_allclose(np.degrees(undeclined.dip_direction), [350.0, 80.0, 170.0], atol=1e-9)


# ---------------------------------------------------------------------------------------------------
# Terzaghi's weights


def test_terzaghi_weights_on_a_scanline(tmp_path):
    """Scanline trend 090 plunge 0, so cos delta = n . (1, 0, 0) = sin(dip) sin(dip direction): 60/090:
    1/sin 60 = 1.1547; 30/090: 1/sin 30 = 2; 80/000 (parallel to the line): the cap 1/sin 15 = 3.8637;
    10/090: 1/sin 10 = 5.7588, capped at 3.8637, or kept under a cap of 10."""
    path = _write(tmp_path, "dip_deg,dip_direction_deg\n60,90\n30,90\n80,0\n10,90\n")
    line = SamplingLine(np.radians(90.0), 0.0)
    expected = [1.0 / np.sin(np.radians(60.0)), 2.0, CAP, CAP]
    np.testing.assert_allclose(read_readings(path, sampling=line).weights, expected, atol=1e-9)
    loose = read_readings(path, sampling=line, max_weight=10.0)
    assert loose.weights[3] == pytest.approx(1.0 / np.sin(np.radians(10.0)), abs=1e-9)
    assert loose.max_weight == 10.0
    per_row = _write(tmp_path, (
        "dip_deg,dip_direction_deg,line_trend_deg,line_plunge_deg\n"
        "60,90,90,0\n30,90,90,0\n80,0,90,0\n10,90,,\n"
    ), "rows.csv")  # fmt: skip
    np.testing.assert_allclose(read_readings(per_row).weights, [*expected[:3], 1.0], atol=1e-9)


def test_terzaghi_weights_on_a_mapped_face(tmp_path):
    """A vertical face dipping to 000 (pole (0, 1, 0)): w = 1 / sin theta, theta between the plane and
    the face (Dips' planar traverse). 90/090: theta 90, w 1; 45/000: cos theta = sin 45, w = 1/sin 45 =
    1.4142; 80/000: theta 10, 1/sin 10 capped at 1/sin 15; the face itself (90/000): capped."""
    path = _write(tmp_path, "dip_deg,dip_direction_deg\n90,90\n45,0\n80,0\n90,180\n")
    face = SamplingFace(np.radians(90.0), 0.0)
    expected = [1.0, np.sqrt(2.0), CAP, CAP]
    np.testing.assert_allclose(read_readings(path, sampling=face).weights, expected, atol=1e-9)
    per_row = _write(tmp_path, (
        "dip_deg,dip_direction_deg,face_dip_deg,face_dip_direction_deg,weight\n"
        "90,90,90,0,\n45,0,90,0,3\n80,0,90,0,\n90,180,90,0,\n"
    ), "rows.csv")  # fmt: skip
    readings = read_readings(per_row)
    np.testing.assert_allclose(readings.terzaghi, expected, atol=1e-9)
    np.testing.assert_allclose(readings.weights, [1.0, 3.0 * np.sqrt(2.0), CAP, CAP], atol=1e-9)


# ---------------------------------------------------------------------------------------------------
# bad input: one line naming the file, the row's line and the column


def _refused(path: Path, *where: str, **options) -> str:
    with pytest.raises(ConfigError) as caught:
        read_readings(path, **options)
    message = str(caught.value)
    assert "\n" not in message
    assert message.startswith(str(path))
    for part in where:
        assert part in message, message
    return message


HEADER = "dip_deg,dip_direction_deg\n"
BAD_CELLS = {
    "a dip of 120": (HEADER + "60,120\n120,10\n", "line 3", "'dip_deg'", "got 120"),
    "a dip direction of 400": (HEADER + "60,400\n", "line 2", "'dip_direction_deg'", "got 400"),
    "a negative dip": (HEADER + "-5,40\n", "line 2", "'dip_deg'"),
    "a pole plunge of 95": ("pole_trend_deg,pole_plunge_deg\n10,95\n", "line 2", "'pole_plunge_deg'"),
    "a pole plunge below 0": ("pole_trend_deg,pole_plunge_deg\n10,-3\n", "line 2", "'pole_plunge_deg'"),
    "an alpha of 95": ("alpha_deg,beta_deg,hole_trend_deg,hole_plunge_deg\n95,10,0,60\n", "'alpha_deg'"),
    "a hole plunge of 100": ("alpha_deg,beta_deg,hole_trend_deg,hole_plunge_deg\n45,10,0,100\n",
                             "line 2", "'hole_plunge_deg'"),
    "a scanline plunge of -10": (HEADER + "60,10\n", "line 2"),  # replaced below with its own file
    "a word for a dip": (HEADER + "60,10\nsteep,10\n", "line 3", "'dip_deg'", "not a number"),
    "a word for an azimuth": (HEADER + "60,east\n", "line 2", "'dip_direction_deg'", "not a number"),
    "a quadrant bearing past 90": (HEADER + "60,N95E\n", "line 2", "'dip_direction_deg'", "N95E"),
    "a weight below 0": (HEADER.strip() + ",weight\n60,10,-1\n", "line 2", "'weight'"),
    "a trace length of 0": (HEADER.strip() + ",trace_length_m\n60,10,0\n", "line 2", "'trace_length_m'"),
    "a strike without its dip": ("strike_deg,dip_deg\n30,40\n30,\n", "line 3", "'dip_deg'", "blank"),
    "a dip without its direction": (HEADER + "60,10\n60,\n", "line 3", "'dip_direction_deg'"),
    "a row with no orientation": (HEADER.strip() + ",type\n60,10,joint\n,,\n,,fault\n", "line 4",
                                  "'dip_direction_deg'", "no orientation in this row"),
    "azimuths and bearings in one column": (HEADER + "60,120\n60,N30E\n", "line 3", "'dip_direction_deg'",
                                            "mixed conventions in one column"),
    "two conventions in one row": ("dip_deg,dip_direction_deg,strike_deg\n60,120,\n60,120,30\n", "line 3",
                                   "'dip_direction_deg'", "mixed conventions in one row"),
    "a line trend without its plunge": (HEADER.strip() + ",line_trend_deg,line_plunge_deg\n60,10,90,\n",
                                        "line 2", "'line_plunge_deg'"),
    "a line and a face in one row": (HEADER.strip() + ",line_trend_deg,line_plunge_deg,face_dip_deg,"
                                     "face_dip_direction_deg\n60,10,90,0,80,10\n", "line 2", "two sampling"),
    "a core reading with no hole": ("alpha_deg,beta_deg\n45,10\n", "line 2", "'hole_trend_deg'"),
    "a core reading with a scanline": ("alpha_deg,beta_deg,hole_trend_deg,hole_plunge_deg,line_trend_deg,"
                                       "line_plunge_deg\n45,10,0,60,0,0\n", "line 2", "'line_trend_deg'"),
}  # fmt: skip
BAD_CELLS["a scanline plunge of -10"] = (
    HEADER.strip() + ",line_trend_deg,line_plunge_deg\n60,10,90,-10\n",
    "line 2",
    "'line_plunge_deg'",
)


@pytest.mark.parametrize("case", BAD_CELLS)
def test_a_bad_cell_is_one_line_naming_file_line_and_column(tmp_path, case):
    text, *where = BAD_CELLS[case]
    _refused(_write(tmp_path, text), *where)


def test_the_line_counts_the_comments_and_a_workbook_says_row(tmp_path):
    _refused(
        _write(tmp_path, "# site\n# date\n" + HEADER + "60,10\n60,400\n"), "line 5", "'dip_direction_deg'"
    )
    pd.DataFrame({"dip_deg": [60, 120], "dip_direction_deg": [10, 10]}).to_excel(
        tmp_path / "s.xlsx", index=False
    )
    _refused(tmp_path / "s.xlsx", "row 3", "'dip_deg'", "got 120")


BAD_FILES = {
    "an empty file": ("", "empty"),
    "comments only": ("# nothing yet\n\n", "empty"),
    "a header and no readings": (HEADER, "no data rows"),
    "no orientation columns": ("type,location\njoint,bench\n", "no orientation columns"),
    "strike without dip": ("strike_deg,type\n30,joint\n", "missing column 'dip_deg'"),
    "alpha without beta": ("alpha_deg\n30\n", "missing column 'beta_deg'"),
    "not text": ("\0\1\2", "NUL"),
}


@pytest.mark.parametrize("case", BAD_FILES)
def test_a_bad_file_is_one_line_naming_it(tmp_path, case):
    text, said = BAD_FILES[case]
    _refused(_write(tmp_path, text), said)


def test_bad_options_name_the_file_and_the_key(tmp_path):
    path = _write(tmp_path, HEADER + "60,10\n")
    _refused(path, "convention 'rhr'", "dip_direction, strike_rhr, pole, core", convention="rhr")
    _refused(path, "missing column 'pole_trend_deg'", convention="pole")
    _refused(path, "core reference 'side'", core_reference="side")
    _refused(tmp_path / "absent.csv", "cannot read")
    (tmp_path / "broken.xlsx").write_bytes(b"not a workbook")
    _refused(tmp_path / "broken.xlsx", "cannot read as an Excel workbook")
