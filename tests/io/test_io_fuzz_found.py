"""The failures the readers' fuzz suite (``test_io_fuzz.py``) found, each kept as a plain
regression test: the input that failed, the clear error it gives now."""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from helpers.io_cases import write
from helpers.reader_fuzz import meshio_seeds

from geomexact import io
from geomexact.errors import FormatError
from geomexact.io.registry import PROBLEM_LIMIT


def read_error(path: Path) -> FormatError:
    with pytest.raises(FormatError) as caught:
        io.read(path)
    return caught.value


def test_geomview_appearance_at_the_end_names_its_own_line(tmp_path: Path) -> None:
    """``{ appearance`` and nothing after: was an error on line 2 of a one-line file."""
    error = read_error(write(tmp_path, "g.off", "{ appearance"))
    assert error.line == 1 and "'appearance' must be followed by '{ … }'" in error.problem


def test_geomview_block_with_a_long_line_is_read_in_linear_time(tmp_path: Path) -> None:
    """An appearance block holding a 400,000-character line: blanking it character by
    character took 10 s (quadratic); now a few milliseconds."""
    text = ("{ appearance { +edge " + "1 " * 200_000 + "}\nOFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n"
            "3 0 1 2\n}\n")
    began = time.perf_counter()
    _, notes = io.read_with_notes(write(tmp_path, "g.off", text))
    assert time.perf_counter() - began < 1.0
    assert "read the OFF object inside a Geomview '{ … }' wrapper" in notes


def test_a_huge_count_is_clipped_in_the_message(tmp_path: Path) -> None:
    """A hole count of 1,000 digits (int() converts it): the message quoted it whole,
    twice (over 2,000 characters)."""
    count = "1" + "7" * 999
    error = read_error(write(tmp_path, "p.poly", f"3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n0 0\n{count}\n"))
    assert "expected 1777" in error.problem and "(1,000 characters)" in error.problem
    assert len(error.problem) < 400


def test_a_huge_label_is_cut_by_the_safety_net(tmp_path: Path) -> None:
    """A 4,000-digit vertex number (not consecutive): no message over the limit."""
    label = "9" * 4000
    error = read_error(write(tmp_path, "n.node", f"2 2 0 0\n0 0 0\n{label} 1 0\n"))
    assert error.line == 3 and len(error.problem) <= PROBLEM_LIMIT + 60


MESHIO = {case.name: case for case in meshio_seeds()}
needs_meshio = pytest.mark.skipif(not MESHIO, reason="meshio is not installed")


def _msh(tmp_path: Path, change: str, to: str) -> Path:
    text = MESHIO["msh41"].files["m.msh"].decode()
    assert change in text
    return write(tmp_path, "m.msh", text.replace(change, to, 1))


@needs_meshio
def test_gmsh_with_a_long_section_name_does_not_hang(tmp_path: Path) -> None:
    """``$Elements`` followed by 200,000 digits: meshio's warning about the unclosed
    section went through rich's highlighting regex, which ran for minutes.  meshio's
    warnings are now collected (notes), and the read ends at once."""
    path = _msh(tmp_path, "$Elements\n", "$Elements" + "7" * 200_000 + "\n")
    began = time.perf_counter()
    with pytest.raises(FormatError):
        io.read(path)
    assert time.perf_counter() - began < 5.0


@needs_meshio
def test_gmsh_with_a_huge_node_tag_fails_instead_of_filling_memory(tmp_path: Path) -> None:
    """Node tag 2^31: meshio made an array of 2^31 + 1 integers (16 GiB) to invert the
    tags.  Under the read's address-space budget that allocation fails, reported as the
    file's problem."""
    path = _msh(tmp_path, "\n7\n8\n9\n", "\n2147483648\n8\n9\n")
    error = read_error(path)
    assert error.line is None and "more memory than a file of this size" in error.problem


@needs_meshio
def test_gmsh_triangle_cells_of_the_wrong_shape(tmp_path: Path) -> None:
    """A file cut after an element block's header: meshio returns triangle cells of shape
    (8, 0), and unpacking them escaped as ValueError."""
    text = MESHIO["msh41"].files["m.msh"].decode()
    cut = text.index("2 0 2 8\n") + len("2 0 2 8")
    error = read_error(write(tmp_path, "m.msh", text[:cut]))
    assert "expected n x 3" in error.problem
