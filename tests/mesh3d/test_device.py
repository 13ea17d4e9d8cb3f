"""Devices of material boxes (issue 24, item 2): the exact grid fits every box face, each
material's volume equals its painted volume (computed without the octree), the later box
wins where boxes overlap, uncovered space is left out, materials meet face to face; the
device file's errors name the line; a P1 Poisson solve converges on a device mesh."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest
from helpers.device_cases import mos
from helpers.poisson import p1_l2_error, rates

from geomexact.errors import FormatError
from geomexact.io.device_file import read_device, write_device
from geomexact.kernel.numbers import mpq
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.measures import total_volume
from geomexact.mesh3d.octree.device import (
    Device,
    DeviceBox,
    device_planes,
    generate_device,
    painted_volumes,
)
from geomexact.mesh3d.validation import validate3


def test_each_material_has_its_exact_painted_volume() -> None:
    device = mos()
    run = generate_device(device, level=1)
    assert validate3(run.mesh) == []
    assert run.volumes == painted_volumes(device) == {1: mpq(1, 2), 2: mpq(1, 4),
                                                      3: mpq(1, 16)}
    assert total_volume(run.mesh) == sum(run.volumes.values())
    assert run.grid == (3, 3, 3) and len(run.materials) == run.mesh.tetrahedron_count


def _fraction_volume(points: list[tuple[Fraction, ...]]) -> Fraction:
    a, b, c, d = points
    u, v, w = ([q[i] - a[i] for i in range(3)] for q in (b, c, d))
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0])) / 6


def test_materials_independently() -> None:
    """Plain fractions: every tetrahedron positive, inside the last box holding its
    centre, with that box's material; interfaces are faces of both sides."""
    device = Device((DeviceBox(Box((0, 0, 0), (3, 1, 1)), 1),
                     DeviceBox(Box((1, 0, 0), (2, 1, mpq(1, 2))), 2)))  # 2 overrides 1
    run = generate_device(device)
    boxes = [([Fraction(str(v)) for v in item.box.low], [Fraction(str(v)) for v in
              item.box.high], item.material) for item in device.boxes]
    for tetrahedron, material in zip(run.mesh.tetrahedra(), run.materials.tolist(),
                                     strict=True):
        points = [tuple(Fraction(str(c)) for c in run.mesh.point(v)[:3]) for v in tetrahedron]
        assert _fraction_volume(points) > 0
        centre = [sum(p[i] for p in points) / 4 for i in range(3)]
        holding = [m for low, high, m in boxes
                   if all(low[i] <= centre[i] <= high[i] for i in range(3))]
        assert holding and holding[-1] == material
        assert all(any(all(low[i] <= p[i] <= high[i] for i in range(3))
                       for low, high, m in boxes if m == material) for p in points)
    assert run.volumes == {1: mpq(5, 2), 2: mpq(1, 2)}


def test_space_no_box_covers_is_left_out() -> None:
    device = Device((DeviceBox(Box((0, 0, 0), (1, 1, 1)), 1),
                     DeviceBox(Box((2, 0, 0), (3, 1, 1)), 2)))
    run = generate_device(device)
    assert total_volume(run.mesh) == 2 and run.volumes == {1: 1, 2: 1}


def test_a_layer_of_any_rational_thickness_is_fitted_exactly() -> None:
    """A layer 1/1000 thick (and one 1/3 thick) are rows of grid cells of the rectilinear
    grid: no grid of equal cubes is needed."""
    thin = Device((DeviceBox(Box((0, 0, 0), (1, 1, 1)), 1),
                   DeviceBox(Box((0, 0, 1), (1, 1, 1 + mpq(1, 1000))), 2),
                   DeviceBox(Box((0, 0, 1 + mpq(1, 1000)), (1, mpq(1, 3), 2)), 3)))
    assert device_planes(thin)[2] == (0, 1, 1 + mpq(1, 1000), 2)
    run = generate_device(thin, level=1)
    assert validate3(run.mesh) == []
    assert run.volumes == painted_volumes(thin) == {1: 1, 2: mpq(1, 1000),
                                                    3: mpq(1, 3) * (1 - mpq(1, 1000))}
    assert run.grid == (1, 2, 3)


def test_the_device_file_round_trips_and_names_bad_lines(tmp_path: Path) -> None:
    path = tmp_path / "mos.device"
    write_device(path, mos())
    assert read_device(path) == mos()
    cases = {
        "first line": "box 0 0 0 1 1 1 1\n",
        "X0 < X1": "geomexact-device 1\nbox 0 0 0 0 1 1 1\n",
        "8 fields": "geomexact-device 1\nbox 0 0 0 1 1 1\n",
        "not an integer": "geomexact-device 1\nbox 0 0 0 1 1 1 one\n",
        "positive": "geomexact-device 1\nbox 0 0 0 1 1 1 0\n",
        "no box": "geomexact-device 1\nmaterial 1 si\n",
        "'material …' or 'box …'": "geomexact-device 1\nsphere 0 0 0 1\n",
        "named twice": "geomexact-device 1\nmaterial 1 a\nmaterial 1 b\nbox 0 0 0 1 1 1 1\n",
        "x": "geomexact-device 1\nbox 0 0 0 1 1 x 1\n",
    }
    for expected, text in cases.items():
        bad = tmp_path / "bad.device"
        bad.write_text(text)
        with pytest.raises(FormatError, match=r"bad\.device") as error:
            read_device(bad)
        assert expected in str(error.value), (expected, str(error.value))
    bad.write_text("geomexact-device 1\n\nbox 0 0 0 1 1 1 1\nbox 0 0 0 1 1 z 2\n")
    with pytest.raises(FormatError, match=r"bad.device:4"):
        read_device(bad)


def test_p1_poisson_on_a_device_converges_at_second_order() -> None:
    errors = [p1_l2_error(generate_device(mos(), level=level).mesh)  # type: ignore[arg-type]
              for level in (0, 1, 2)]
    measured = rates([1, 0.5, 0.25], errors)
    assert all(rate > 1.8 for rate in measured), (errors, measured)  # measured 1.95, 2.00
