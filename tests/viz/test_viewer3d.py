"""The 3D viewer page (:mod:`geomexact.viz.scene3d`): one offline file embedding every
tetrahedron of a cuboid partition's trace with its birth and death steps."""

from __future__ import annotations

import base64
import json
import re
from array import array
from fractions import Fraction

import pytest

from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.viz.scene3d import exact_volume, payload3, radius_ratio, viewer_html_3d

PATTERN = 0b101101


def _data(page: str) -> dict:
    match = re.search(r'<script type="application/json" id="geomexact-data">(.*?)</script>',
                      page, re.S)
    assert match
    return json.loads(match.group(1))


def _ints(text: str, code: str) -> list[int]:
    values = array(code)
    values.frombytes(base64.b64decode(text))
    return list(values)


def test_page_is_one_offline_file_with_tetrahedra_and_steps() -> None:
    run = partition_cuboid(PATTERN, improve=True)
    page = viewer_html_3d(run.start, run.trace, title="cuboid")
    assert page.startswith("<!DOCTYPE html>")
    assert page.count("<script") == 2 and "src=" not in page
    assert not re.search(r"https?://", page)
    assert "<link rel=\"stylesheet\"" not in page
    data = _data(page)
    assert data["format"] == "geomexact-view3d"
    assert data["steps"] == len(run.trace.steps) > 0
    assert data["labels"][1:] == [str(s) for s in run.trace.steps]
    cells = _ints(data["cells"], "I")
    birth, death = _ints(data["birth"], "i"), _ints(data["death"], "i")
    assert len(cells) == 4 * len(birth) == 4 * len(death)
    for step, mesh in ((0, run.start), (data["steps"], run.mesh)):
        alive = sorted(tuple(cells[4 * c:4 * c + 4]) for c in range(len(birth))
                       if birth[c] <= step < death[c])
        assert alive == mesh.tetrahedra()
    assert data["digests"][-1] == run.mesh.digest_text
    assert Fraction(data["volume"]) == exact_volume(run.mesh) == run.box.volume
    assert "split_tetra" in data["ops"]


def test_page_is_deterministic_and_without_trace() -> None:
    run = partition_cuboid(PATTERN)
    assert viewer_html_3d(run.mesh) == viewer_html_3d(run.mesh)
    data = payload3(run.mesh)
    assert data["steps"] == 0
    assert len(_ints(data["birth"], "i")) == run.mesh.tetrahedron_count


def test_options_are_checked() -> None:
    run = partition_cuboid(PATTERN)
    with pytest.raises(ValueError, match="colour"):
        payload3(run.mesh, colour="rainbow")
    with pytest.raises(ValueError, match="step"):
        payload3(run.start, run.trace, step=10_000)


def test_radius_ratio_of_regular_and_flat() -> None:
    from geomexact.kernel.points import point3 as p

    regular = (p(1, 1, 1), p(1, -1, -1), p(-1, 1, -1), p(-1, -1, 1))
    assert radius_ratio(*regular) == pytest.approx(1.0)
    assert radius_ratio(p(0, 0, 0), p(1, 0, 0), p(0, 1, 0), p(1, 1, 0)) == 0.0


def test_empty_mesh_and_wrong_type() -> None:
    from geomexact.mesh3d.snapshot import empty_mesh3

    data = payload3(empty_mesh3())
    assert data["vertex_count"] == 0 and data["volume"] == "0" and data["cells"] == ""
    with pytest.raises(TypeError, match="Mesh3"):
        payload3("not a mesh")  # type: ignore[arg-type]
