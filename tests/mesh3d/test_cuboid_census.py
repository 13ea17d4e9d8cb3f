"""The census runs: the same rows, in pattern order, in this process, on a local process
pool (in chunks) and on a real local Dask cluster on loopback; the patterns' syntax; the
row layout shared by the kernel and the reference; the summary."""

from __future__ import annotations

import importlib.util
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from geomexact.errors import MissingDependencyError, PreconditionError
from geomexact.mesh3d.cuboid import census_runs
from geomexact.mesh3d.cuboid.boxes import box_of_extents, unit_cube
from geomexact.mesh3d.cuboid.census import (
    CENSUS_COLUMNS,
    census_row,
    kind_mask,
    kinds_of_mask,
    summarize,
)
from geomexact.mesh3d.cuboid.census_runs import (
    CensusJob,
    Chunk,
    chunk_rows,
    chunks_of,
    parse_patterns,
    row_values,
    rows_of_values,
    run_census,
)


def test_the_patterns_syntax() -> None:
    assert parse_patterns("all") == range(1, 2**18)
    assert parse_patterns("3-7") == range(3, 8)  # inclusive
    assert parse_patterns("9,2,70688") == (9, 2, 70688)
    for bad in ("7-3", "x", "1-300000", "-1", "2,,3", ""):
        with pytest.raises(PreconditionError):
            parse_patterns(bad)


def test_chunks_are_ranges_not_single_patterns() -> None:
    assert chunks_of(range(1, 11), 4) == [Chunk(1, 5), Chunk(5, 9), Chunk(9, 11)]
    assert [list(c) for c in chunks_of((5, 3, 9), 2)] == [[5, 3], [9]]


def test_the_row_layout_round_trips() -> None:
    box = box_of_extents(1, 2, 4)
    job = CensusJob(box, "index", 1, True, False, "reference")
    for pattern in (1, 4096, 70688):
        row = census_row(pattern, box, order="index", template=1, improve=True)
        assert rows_of_values(job, Chunk(0, 0, (pattern,)), row_values(row)) == [row]
    assert kinds_of_mask(kind_mask(["N32", "T22"])) == ("N32", "T22")


@pytest.mark.parametrize("improve", [False, True])
def test_the_reference_and_the_kernel_and_the_pool_give_the_same_rows(improve: bool) -> None:
    patterns = parse_patterns("4080-4130")
    reference = run_census(patterns, CensusJob(unit_cube(), improve=improve,
                                               engine="reference"), workers=1)
    auto = run_census(patterns, CensusJob(unit_cube(), improve=improve), workers=1)
    pool = run_census(patterns, CensusJob(unit_cube(), improve=improve), workers=2,
                      chunk_size=7)
    assert reference == auto == pool
    assert [row.pattern for row in pool] == list(patterns)


def test_a_chunk_comes_back_as_one_array_of_rows() -> None:
    # an array crosses Dask as one buffer; a list went int by int
    job = CensusJob(unit_cube(), improve=True)
    for chunk in (Chunk(4090, 4110), Chunk(0, 0, (70688, 3, 4096))):
        values = chunk_rows(job, chunk)
        assert isinstance(values, np.ndarray)
        assert values.dtype == np.int32 and values.shape == (len(chunk), 12)
        rows = rows_of_values(job, chunk, values)
        assert all(type(row.tetrahedra) is int for row in rows)
        assert rows == [census_row(p, unit_cube(), improve=True) for p in chunk]


def test_threads_of_one_process_give_the_same_rows() -> None:
    # a Dask worker runs tasks on several threads of one process, the kernel without the GIL
    job = CensusJob(box_of_extents(1, 2, 4), improve=True)
    chunks = chunks_of(range(4000, 16000), 1000)
    alone = [chunk_rows(job, chunk) for chunk in chunks]
    with ThreadPoolExecutor(max_workers=4) as threads:
        together = list(threads.map(lambda chunk: chunk_rows(job, chunk), chunks))
    assert all(np.array_equal(a, b) for a, b in zip(alone, together, strict=True))


def test_progress_is_reported_per_chunk() -> None:
    seen: list[tuple[int, int]] = []
    run_census(range(1, 41), CensusJob(unit_cube()), workers=1, chunk_size=16,
               on_progress=lambda done, total: seen.append((done, total)))
    assert seen == [(16, 40), (32, 40), (40, 40)]


def test_the_summary_counts_rows() -> None:
    rows = run_census(parse_patterns("1,2,4096,262143"), CensusJob(unit_cube(), improve=True),
                      workers=1)
    (summary,) = summarize(rows)
    assert summary.patterns == 4 and summary.valid == 4
    assert summary.present["T23"] == sum(row.has("T23") for row in rows)
    assert summary.flips["flip23"] == sum(row.flips[0] for row in rows if row.flips)
    report = summary.report()
    assert report["patterns"] == 4 and "failing_improved_percent" in report
    assert set(rows[0].record()) == set(CENSUS_COLUMNS)


def test_a_missing_dask_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    real = importlib.import_module

    def blocked(name: str, *args: object) -> object:
        if name == "distributed":
            raise ImportError("blocked")
        return real(name, *args)  # type: ignore[arg-type]

    monkeypatch.setattr(census_runs.importlib, "import_module", blocked)
    with pytest.raises(MissingDependencyError, match=r"geomexact\[cluster\]"):
        run_census(range(1, 3), CensusJob(unit_cube()), dask_address="tcp://127.0.0.1:1")


@pytest.mark.skipif(importlib.util.find_spec("distributed") is None,
                    reason="dask[distributed] is not installed (the 'cluster' extra)")
def test_a_real_local_dask_cluster_gives_the_same_rows() -> None:
    distributed = importlib.import_module("distributed")
    job = CensusJob(box_of_extents(1, 2, 4), order="index", improve=True)
    patterns = parse_patterns("4000-4600")
    listed = (70688, 5, 4096, 262143, 4100)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=2, host="127.0.0.1",
                                  processes=True, dashboard_address=None) as cluster:
        on_dask = run_census(patterns, job, dask_address=cluster.scheduler_address,
                             chunk_size=100)
        sized = run_census(patterns, job, dask_address=cluster.scheduler_address)
        listed_on_dask = run_census(listed, job, dask_address=cluster.scheduler_address,
                                    chunk_size=2)
    assert on_dask == sized == run_census(patterns, job, workers=2, chunk_size=64)
    assert on_dask == run_census(patterns, job, workers=1)
    assert [row.pattern for row in on_dask] == list(patterns)
    assert listed_on_dask == run_census(listed, job, workers=1)
