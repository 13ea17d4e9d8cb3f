"""The bulk writers (issue 15, item 2) write the same bytes as the writers they replace
(``legacy_writers``), in every number style, on the shared data, on random meshes and on
numbers at the edges: 1e-400 and 1e400, 17 significant digits, p/q, dyadics; and count
the same rounded numbers."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest
from helpers.io_cases import grid_meshes, pslgs
from helpers.legacy_writers import (
    LegacyNumberText,
    off_text,
    poly_text,
    pslg_node_text,
    tetgen_texts,
    triangle_texts,
)
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_io_shared_data import EVERY_FILE

from geomexact import io, mesh_from_triangles, mpq, point2
from geomexact.io.registry import (
    FILE_SET_MARK,
    NUMBER_STYLES,
    NumberStyle,
    NumberText,
    exact_decimal_text,
)
from geomexact.kernel.numbers import Rational, dyadic_decimal, exact_decimal
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.mesh3d.snapshot import Mesh3


def _written(path: Path, value: object, style: NumberStyle) -> tuple[dict[str, str], int]:
    """The texts the registry's writer writes for ``value`` at ``path``, by extension,
    and how many numbers it rounded."""
    report = io.write_with_report(path, value, numbers=style, overwrite=True)  # type: ignore[arg-type]
    texts = {}
    stamps = set()
    for written in report.paths:
        text = written.read_text()
        if len(report.paths) > 1:  # a file set: the same stamp ends every file of it
            body, stamp = text.rstrip("\n").rsplit("\n", 1)
            assert stamp.startswith(FILE_SET_MARK), written
            stamps.add(stamp)
            text = body + "\n"
        texts[written.suffix] = text
    assert len(stamps) <= 1
    return texts, report.rounded


def _legacy(value: object, suffix: str, style: NumberStyle) -> tuple[dict[str, str], int]:
    number = LegacyNumberText(style)
    if isinstance(value, Mesh3):
        return tetgen_texts(value, number), number.rounded
    if isinstance(value, Mesh2) and suffix == ".ele":
        return triangle_texts(value, number), number.rounded
    if isinstance(value, Mesh2 | PolygonMesh):
        return {".off": off_text(value, number)}, number.rounded
    assert isinstance(value, PSLG)
    if suffix == ".node":
        return {".node": pslg_node_text(value, number)}, number.rounded
    return {".poly": poly_text(value, number)}, number.rounded


def _suffixes(value: object) -> list[str]:
    if isinstance(value, Mesh3):
        return [".ele"]
    if isinstance(value, Mesh2):
        return [".ele", ".off"]
    if isinstance(value, PolygonMesh):
        return [".off"]
    return [".node", ".poly"]


def _same_bytes(directory: Path, value: object) -> None:
    for suffix in _suffixes(value):
        for style in NUMBER_STYLES:
            new = _written(directory / f"m{suffix}", value, style)
            old = _legacy(value, suffix, style)
            assert new == old, (suffix, style)


@pytest.mark.parametrize("name", EVERY_FILE)
def test_shared_data_is_written_byte_for_byte_as_before(
    shared_data: Path, tmp_path: Path, name: str
) -> None:
    if name.endswith(".txt"):
        pytest.skip("a triangle list: its writer is not a bulk writer")
    _same_bytes(tmp_path, io.read(shared_data / name))


_EDGE_VALUES = [
    mpq(1, 10**400), mpq(-(10**400)), mpq(10**400) + mpq(1, 3), mpq(1, 3) * mpq(10) ** -400,
    mpq(12345678901234567, 10**17), mpq(-98765432109876543, 10**5), mpq(1, 3), mpq(-22, 7),
    mpq(1, 2**80), mpq(3, 2**1100), mpq(2**1100), mpq(10**20), mpq(-(10**8)), mpq(5, 2),
    mpq(0), mpq(7, 2**1080), mpq(1, 10**9), mpq(2**53 + 1), mpq(-(2**53)), mpq(1, 1024),
]


def _values() -> st.SearchStrategy[Rational]:
    fractions = st.fractions(max_denominator=10**6).map(
        lambda f: mpq(f.numerator, f.denominator)
    )
    decimals = st.builds(
        lambda k, power: mpq(k) * mpq(10) ** power,
        st.integers(-(10**18), 10**18), st.integers(-420, 420),
    )
    dyadics = st.builds(
        lambda k, power: mpq(k) * mpq(2) ** power,
        st.integers(-(2**60), 2**60), st.integers(-1100, 1100),
    )
    return st.one_of(st.sampled_from(_EDGE_VALUES), fractions, decimals, dyadics)


@given(_values())
def test_number_text_is_the_legacy_text(value: Rational) -> None:
    for style in NUMBER_STYLES:
        new, old = NumberText(style), LegacyNumberText(style)
        assert new(value) == old(value) and new(value) == old(value)
        assert new.rounded == old.rounded
    dyadic = dyadic_decimal(value, plain_within=8)
    if dyadic is not None:
        assert dyadic == exact_decimal_text(value) == exact_decimal(value, plain_within=8)
        assert dyadic_decimal(value) == exact_decimal(value)


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture], max_examples=40)
@given(mesh=st.one_of(grid_meshes(), grid_meshes(dyadic=True)), values=st.data())
def test_random_meshes_are_written_byte_for_byte_as_before(
    tmp_path: Path, mesh: Mesh2, values: st.DataObject
) -> None:
    _same_bytes(tmp_path, mesh)
    # the same triangles with coordinates at the edges of the number styles
    scale = values.draw(_values().filter(lambda v: v != 0))
    shift = values.draw(_values())
    moved = mesh_from_triangles(
        [point2(p.x * scale + shift, p.y * scale - shift) for p in
         (mesh.vertices[i] for i in range(mesh.vertex_count))],
        mesh.triangles(), orient=True,
    )
    _same_bytes(tmp_path, moved)


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture], max_examples=25)
@given(pslg=st.one_of(pslgs(), pslgs(dyadic=True)))
def test_random_pslgs_are_written_byte_for_byte_as_before(tmp_path: Path, pslg: PSLG) -> None:
    _same_bytes(tmp_path, pslg)


rationals = st.fractions(min_value=-10, max_value=10, max_denominator=12)


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture], max_examples=15)
@given(
    pattern=st.integers(0, 2**18 - 1),
    low=st.tuples(rationals, rationals, rationals),
    size=st.tuples(*[st.fractions(min_value=Fraction(1, 7), max_value=5,
                                  max_denominator=9)] * 3),
)
def test_tetgen_meshes_are_written_byte_for_byte_as_before(
    tmp_path: Path,
    pattern: int,
    low: tuple[Fraction, Fraction, Fraction],
    size: tuple[Fraction, Fraction, Fraction],
) -> None:
    box = Box(low, tuple(lo + s for lo, s in zip(low, size, strict=True)))
    _same_bytes(tmp_path, partition_cuboid(pattern, box).mesh)
