"""Written files are the mesh that was reported: lossless numbers by default, every
rounding counted, what a format cannot hold reported (issue 11, part 1)."""

from __future__ import annotations

from decimal import Decimal, localcontext
from fractions import Fraction
from pathlib import Path

import attrs
import pytest
from helpers.io_cases import geometric_triangles, grid_meshes, plain, pslgs
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact import Mesh2, io, mpq, point2
from geomexact.errors import FormatError
from geomexact.io.registry import (
    NumberText,
    exact_decimal_text,
    nearest_double_text,
    short_decimal_text,
)
from geomexact.kernel.numbers import Rational, parse_rational
from geomexact.mesh2d.pslg import PSLG

# (name, holds everything of a Mesh2) for every text format that writes a mesh
_MESH_FILES = [("m.ele", True), ("m.pslg", True), ("m.off", False)]


def _finite_decimals() -> st.SearchStrategy[Rational]:
    """Numbers with a finite decimal expansion: decimals, dyadics and their mixtures, from
    tiny to huge."""
    return st.builds(
        lambda k, twos, fives, power: mpq(k, 2**twos * 5**fives) * mpq(10) ** power,
        st.integers(-(10**20), 10**20),
        st.integers(0, 60),
        st.integers(0, 30),
        st.integers(-400, 400),
    )


@given(_finite_decimals())
def test_a_finite_decimal_is_written_as_itself(value: Rational) -> None:
    text = exact_decimal_text(value)
    assert text is not None
    assert parse_rational(text) == value
    numbers = NumberText("decimal")
    assert numbers(value) == text and numbers.rounded == 0


@given(
    st.fractions().filter(lambda f: f.denominator % 3 == 0 or f.denominator % 7 == 0),
    st.integers(-400, 400),
)
def test_a_value_without_a_finite_decimal_is_rounded_or_written_as_p_over_q(
    fraction: Fraction, power: int
) -> None:
    value = mpq(fraction.numerator, fraction.denominator) * mpq(10) ** power
    assert exact_decimal_text(value) is None
    exact = NumberText("exact")
    assert parse_rational(exact(value)) == value and exact.rounded == 0
    decimal = NumberText("decimal")
    rounded = parse_rational(decimal(value))
    assert decimal.rounded == 1
    # the nearest double, or 17 significant digits outside the normal doubles: either way
    # within one unit in the 16th significant digit, and never zero or infinite
    assert abs(rounded - value) <= abs(value) * mpq(1, 10**15)


@given(st.fractions(), st.integers(-400, 400))
def test_rounding_outside_the_doubles_is_correct_to_17_digits(
    fraction: Fraction, power: int
) -> None:
    value = mpq(fraction.numerator, fraction.denominator) * mpq(10) ** power
    text, exact = nearest_double_text(value)
    written = parse_rational(text)
    assert exact == (written == value)
    if value != 0 and not mpq(2) ** -1030 < abs(value) < mpq(2) ** 1030:
        with localcontext() as context:
            context.prec = 3000  # far more digits than any rounding tie could need
            precise = Decimal(fraction.numerator) * Decimal(10) ** power / Decimal(
                fraction.denominator
            )
            context.prec = 17  # then one correct half-even rounding
            expected = +precise
        assert written == parse_rational(str(expected))


def test_the_float_style_counts_every_rounded_number() -> None:
    numbers = NumberText("float")
    assert numbers(parse_rational("554.36621710365398")) == "554.366217103654"
    assert numbers(parse_rational("0.5")) == "0.5"
    assert numbers(parse_rational("1e309")) == "1e309"  # kept, beyond the doubles
    assert numbers(mpq(10**20 + 1)) == "1e+20"
    assert numbers.rounded == 2


def test_the_issue_number_is_kept_by_default(tmp_path: Path) -> None:
    """``554.36621710365398`` became ``554.366217103654`` in every written file."""
    x = parse_rational("554.36621710365398")
    mesh_points = [point2(x, 0), point2(x + 1, 0), point2(x, 1)]
    from geomexact import mesh_from_triangles

    mesh = mesh_from_triangles(mesh_points, [(0, 1, 2)])
    for name, _ in _MESH_FILES:
        report = io.write_with_report(tmp_path / name, mesh)
        assert report.rounded == 0
        assert io.read(tmp_path / name).point(0).x == x


@settings(max_examples=40, deadline=None)
@given(grid_meshes(dyadic=False, extras=True), st.data())
def test_every_format_round_trips_every_kind_of_mesh_digest_exact(
    tmp_path_factory: pytest.TempPathFactory, mesh: Mesh2, data: st.DataObject
) -> None:
    """Markers, attributes, regions and segments: the formats that hold them give the same
    digest back by default; OFF gives the plain mesh's digest and says what it dropped;
    the triangle list keeps the geometry; numbers without a finite decimal expansion are
    exact with numbers="exact"."""
    del data
    directory = tmp_path_factory.mktemp("round")
    for name, holds_all in _MESH_FILES:
        report = io.write_with_report(directory / name, mesh, numbers="exact")
        assert report.rounded == 0
        back = io.read(directory / name)
        assert isinstance(back, Mesh2)
        if holds_all:
            assert back.digest == mesh.digest, name
            assert report.dropped == ()
        else:
            assert back.digest == plain(mesh).digest, name
            has_extras = bool(
                mesh.segments or mesh.triangle_attributes or mesh.vertex_attributes
                or any(mesh.vertex_markers.values())
            )
            assert bool(report.dropped) == has_extras
    report = io.write_with_report(directory / "m.txt", mesh, numbers="exact")
    assert geometric_triangles(io.read(directory / "m.txt")) == geometric_triangles(mesh)


@settings(max_examples=40, deadline=None)
@given(grid_meshes(dyadic=True, extras=True))
def test_dyadic_meshes_round_trip_by_default_in_every_format(
    tmp_path_factory: pytest.TempPathFactory, mesh: Mesh2
) -> None:
    """Dyadic coordinates (midpoints, grid centroids) have finite decimals: lossless in
    the default style, and exact doubles through meshio (VTU, VTK and Gmsh keep the
    segments, markers and attributes too: issue 26, item 3; Medit drops them and says so).
    """
    directory = tmp_path_factory.mktemp("dyadic")
    for name, holds_all in [*_MESH_FILES, ("m.vtu", True), ("m.vtk", True), ("m.msh", True),
                            ("m.mesh", False)]:
        report = io.write_with_report(directory / name, mesh)
        assert report.rounded == 0, name
        back = io.read(directory / name)
        assert back.digest == (mesh if holds_all else plain(mesh)).digest, name


@settings(max_examples=40, deadline=None)
@given(pslgs(dyadic=False))
def test_pslgs_round_trip_exactly_and_node_files_say_what_they_drop(
    tmp_path_factory: pytest.TempPathFactory, pslg: PSLG
) -> None:
    directory = tmp_path_factory.mktemp("pslg")
    for name in ("p.poly", "p.pslg"):
        report = io.write_with_report(directory / name, pslg, numbers="exact")
        assert report.dropped == () and report.rounded == 0
        assert _zero_markers(io.read(directory / name)) == _zero_markers(pslg)
    report = io.write_with_report(directory / "p.node", pslg, numbers="exact")
    lost = len(pslg.segments) + len(pslg.holes) + len(pslg.regions)
    assert bool(report.dropped) == bool(lost)


def _zero_markers(pslg: object) -> PSLG:
    """``pslg`` with absent vertex markers written out as zeros (the files' reading)."""
    assert isinstance(pslg, PSLG)
    return attrs.evolve(pslg, vertex_markers=pslg.vertex_markers or (0,) * len(pslg.vertices))


def test_meshio_refuses_exact_numbers_before_writing(tmp_path: Path) -> None:
    from geomexact import mesh_from_triangles

    mesh = mesh_from_triangles([(0, 0), (1, 0), (mpq(1, 3), 1)], [(0, 1, 2)])
    with pytest.raises(FormatError, match="cannot hold exact numbers"):
        io.write(tmp_path / "m.vtu", mesh, numbers="exact")
    assert list(tmp_path.iterdir()) == []
    report = io.write_with_report(tmp_path / "m.vtu", mesh)
    assert report.rounded == 1


def test_meshio_names_a_vertex_beyond_the_doubles(tmp_path: Path) -> None:
    from geomexact import mesh_from_triangles

    mesh = mesh_from_triangles([(0, 0), (mpq(10) ** 309, 0), (0, 1)], [(0, 1, 2)])
    with pytest.raises(FormatError, match="vertex 1 has a coordinate beyond the range"):
        io.write(tmp_path / "m.vtu", mesh)
    assert list(tmp_path.iterdir()) == []


def test_exact_decimal_text_prefers_the_plain_form() -> None:
    assert exact_decimal_text(mpq(1000)) == "1000"
    assert exact_decimal_text(mpq(1, 1024)) == "0.0009765625"
    assert exact_decimal_text(mpq(10) ** 40) == "1e40"
    assert exact_decimal_text(mpq(15, 10**31)) == "1.5e-30"
    assert exact_decimal_text(mpq(-1, 2)) == "-0.5"
    assert exact_decimal_text(mpq(0)) == "0"
    assert exact_decimal_text(mpq(1, 3)) is None
    # gmpy2's digits have no int-to-str limit (Python's default is 4300 digits)
    huge = mpq(10**5000 + 1)
    assert parse_rational(exact_decimal_text(huge) or "") == huge


def test_decimal_module_agrees_on_a_long_expansion() -> None:
    value = mpq(123456789, 2**70)
    text = exact_decimal_text(value)
    assert text is not None
    with localcontext() as context:
        context.prec = 200
        assert Decimal(text) == Decimal(123456789) / Decimal(2**70)


@settings(max_examples=400, deadline=None)
@given(st.floats(min_value=-1e16, max_value=1e16, allow_nan=False, allow_infinity=False)
       | st.decimals(min_value=-10**6, max_value=10**6, places=9, allow_nan=False,
                     allow_infinity=False).map(float),
       st.integers(min_value=0, max_value=3))
def test_the_short_decimal_path_gives_the_exact_decimal_text(double: float, offset: int) -> None:
    """A value that is the shortest text of its double is written as that text without
    factoring its denominator, and that text is exact_decimal_text's; a value just off
    it (offset) falls through to the exact path."""
    value = mpq(repr(double)) + mpq(offset, 10**30)
    fast = short_decimal_text(value)
    if fast is not None:
        assert fast == exact_decimal_text(value)
    if offset:
        assert fast is None
    elif value.denominator != 1 and 0.1 <= abs(double) < 1e15:
        assert fast == repr(double)
