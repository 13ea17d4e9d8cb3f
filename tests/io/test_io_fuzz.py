"""The readers' fuzz suite: every reader (Triangle .node/.ele/.neigh/.poly, OFF with
Geomview blocks and polygons, PSLG text, triangle lists, trace files; the 3D readers:
TetGen .node/.ele/.face, Geomview OFF pictures of a Mesh3, meshio's VTU and VTK of
tetrahedra; and meshio's VTK, VTU and Gmsh of triangles) on mutated valid files gives a
clear FormatError or a well-formed value, never another exception and never a hang (the
contract: ``helpers.reader_fuzz``).  Sampled in CI; ``--runslow``
runs many more examples.  Each failure it found is a plain regression test in
``test_io_fuzz_found.py``."""

from __future__ import annotations

import random
import tempfile
from pathlib import Path

import pytest
from helpers.reader_fuzz import Case, check_read, meshio_seeds, mutate, seeds, seeds3d
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

CASES = {case.name: case for case in (*seeds(), *seeds3d())}
MESHIO_CASES = {case.name: case for case in meshio_seeds()}


def _run(case: Case, which: int, seed: int, count: int) -> str:
    names = sorted(case.files)
    target = names[which % len(names)]
    files = dict(case.files)
    files[target] = mutate(files[target], random.Random(seed), count)
    with tempfile.TemporaryDirectory() as directory:
        return check_read(Path(directory), case, files)


def test_every_seed_reads_as_a_value() -> None:
    """The seeds are valid: unmutated, each reads to a well-formed value (or to the
    clear error its reader gives for it, e.g. OFF of a Mesh3: z != 0)."""
    for case in (*CASES.values(), *MESHIO_CASES.values()):
        with tempfile.TemporaryDirectory() as directory:
            outcome = check_read(Path(directory), case, dict(case.files))
            assert outcome == case.seed_gives, case.name


@pytest.mark.parametrize("name", sorted(CASES))
@given(which=st.integers(0, 3), seed=st.integers(0, 2**32), count=st.integers(1, 4))
@settings(max_examples=60, suppress_health_check=[HealthCheck.too_slow])
def test_mutated_files_give_a_clear_error_or_a_value(
    name: str, which: int, seed: int, count: int
) -> None:
    _run(CASES[name], which, seed, count)


@pytest.mark.skipif(not MESHIO_CASES, reason="meshio is not installed")
@pytest.mark.parametrize("name", sorted(MESHIO_CASES))
@given(seed=st.integers(0, 2**32), count=st.integers(1, 3))
@settings(max_examples=15, suppress_health_check=[HealthCheck.too_slow])
def test_mutated_meshio_files_give_a_clear_error_or_a_value(
    name: str, seed: int, count: int
) -> None:
    _run(MESHIO_CASES[name], 0, seed, count)


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(CASES))
def test_mutated_files_long_run(name: str) -> None:
    """Many more mutations per reader (``--runslow``): 3000 each, seeded."""
    case = CASES[name]
    outcomes = {"value": 0, "error": 0}
    for seed in range(3000):
        outcomes[_run(case, seed % 4, seed, 1 + seed % 4)] += 1
    assert outcomes["error"] > 0


@pytest.mark.slow
@pytest.mark.skipif(not MESHIO_CASES, reason="meshio is not installed")
@pytest.mark.parametrize("name", sorted(MESHIO_CASES))
def test_mutated_meshio_files_long_run(name: str) -> None:
    """Many more mutations per meshio format (``--runslow``): 600 each, seeded."""
    case = MESHIO_CASES[name]
    outcomes = {"value": 0, "error": 0}
    for seed in range(600):
        outcomes[_run(case, 0, seed, 1 + seed % 3)] += 1
    assert outcomes["error"] > 0
