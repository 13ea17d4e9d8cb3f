"""``geomexact info`` reports right angles and areas for tiny and huge meshes (issue 11:
edges near 1e-272 used to report a minimum angle of 0; areas beyond the doubles made the
command fail)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from geomexact.cli import main

TRIANGLE = [(0, 0), (3, 1), (1, 4)]  # angles 47.726…°, 57.528…°, 74.744…°


@pytest.mark.parametrize("exponent", [-272, -150, 0, 150, 200])
def test_info_reports_the_angles_of_a_scaled_triangle(
    exponent: int, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    lines = [f"{x}e{exponent} {y}e{exponent} 0" for x, y in TRIANGLE]
    (tmp_path / "t.off").write_text("OFF\n3 1 0\n" + "\n".join(lines) + "\n3 0 1 2\n")
    assert main(["info", str(tmp_path / "t.off"), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert round(report["min_angle_deg"], 9) == 47.726310994
    assert round(report["max_angle_deg"], 9) == 74.744881297
    if exponent == 200:  # the area, 5.5e400, is beyond the doubles: exact text
        assert report["min_area"] == report["total_area"]
