"""Running the census on many patterns: in this process, on a local process pool (the
default: one worker per core), or on a Dask distributed cluster when an address is given.

Work is sent in chunks (ranges of consecutive patterns, or slices of an explicit list),
never one task per pattern, a few per worker; each chunk comes back as one int32 array of
rows (12 ints per pattern, the kernel's layout, :func:`row_values` for the reference), and
the rows are returned in pattern order whatever the order the chunks finish in: the result
is the same on every path.  Dask is imported only when an address is given (the
``cluster`` extra); its chunks are sized for the cluster's threads.
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from typing import Any, Final, Literal, TypeAlias

import attrs
import numpy as np
import numpy.typing as npt

from geomexact.errors import MissingDependencyError, PreconditionError
from geomexact.mesh3d.cuboid import compiled
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.cuboid.census import CensusRow, census_row
from geomexact.mesh3d.cuboid.numbering import PATTERN_COUNT, check_pattern
from geomexact.mesh3d.cuboid.split_order import check_order
from geomexact.mesh3d.cuboid.templates import check_template

__all__ = [
    "CENSUS_ENGINES",
    "CensusJob",
    "Chunk",
    "ProgressCallback",
    "chunk_rows",
    "chunks_of",
    "parse_patterns",
    "row_values",
    "rows_of_values",
    "run_census",
]

CensusEngine: TypeAlias = Literal["auto", "compiled", "reference"]
CENSUS_ENGINES: Final = ("auto", "compiled", "reference")
ProgressCallback: TypeAlias = Callable[[int, int], None]
"""Called with (patterns done, patterns in all) after each chunk."""
RowArray: TypeAlias = npt.NDArray[np.int32]
"""A chunk's rows: shape (patterns, 12), the kernel's layout."""
ROW_WIDTH: Final = compiled.ROW_WIDTH


@attrs.frozen(slots=True)
class CensusJob:
    """What every chunk of one census shares: the box, order, template, whether to
    improve (and to allow boundary flips) and the engine that computes the rows."""

    box: Box
    order: str = "conforming"
    template: int = 0
    improve: bool = False
    allow_boundary_flips: bool = False
    engine: str = "auto"

    def resolved_engine(self) -> str:
        """"compiled" or "reference": what ``engine`` means for this box here."""
        if self.engine not in CENSUS_ENGINES:
            raise PreconditionError("census", f"unknown engine {self.engine!r}; choose from "
                                    f"{', '.join(CENSUS_ENGINES)}")
        reason = compiled.unsupported(self.box)
        if self.engine == "compiled" and reason is not None:
            raise PreconditionError("census", reason)
        if self.engine == "reference" or reason is not None:
            return "reference"
        return "compiled"

    @property
    def shape(self) -> str:
        return self.box.describe()


@attrs.frozen(slots=True)
class Chunk:
    """Patterns ``start`` .. ``stop - 1`` (when ``patterns`` is None), or ``patterns``."""

    start: int
    stop: int
    patterns: tuple[int, ...] | None = None

    def __len__(self) -> int:
        return self.stop - self.start if self.patterns is None else len(self.patterns)

    def __iter__(self) -> Iterator[int]:
        return iter(range(self.start, self.stop) if self.patterns is None else self.patterns)


def parse_patterns(text: str) -> range | tuple[int, ...]:
    """``"all"`` (1 .. 2**18 - 1), ``"A-B"`` (inclusive) or ``"N,M,…"`` (in that order);
    PreconditionError otherwise."""
    text = text.strip()
    try:
        if text == "all":
            return range(1, PATTERN_COUNT)
        if "-" in text and "," not in text:
            low, high = (int(part) for part in text.split("-", 1))
            check_pattern(low)
            check_pattern(high)
            if high < low:
                raise PreconditionError("census", f"the range {text!r} is empty (B < A)")
            return range(low, high + 1)
        return tuple(check_pattern(int(part)) for part in text.split(","))
    except ValueError as error:
        if isinstance(error, PreconditionError):
            raise
        raise PreconditionError(
            "census", f"patterns are 'all', 'A-B' or 'N,M,...', not {text!r}") from None


def chunks_of(patterns: range | Sequence[int], size: int) -> list[Chunk]:
    """``patterns`` cut into chunks of at most ``size`` (ranges stay ranges)."""
    if size < 1:
        raise PreconditionError("census", f"the chunk size must be >= 1, not {size}")
    if isinstance(patterns, range) and patterns.step == 1:
        return [Chunk(start, min(start + size, patterns.stop))
                for start in range(patterns.start, patterns.stop, size)]
    listed = tuple(patterns)
    return [Chunk(0, 0, listed[i:i + size]) for i in range(0, len(listed), size)]


def row_values(row: CensusRow) -> tuple[int, ...]:
    """The 12 row ints of ``row`` (the kernel's layout; -1 where there is no improvement)."""
    flips = row.flips or (-1, -1, -1, -1)
    return (row.tetrahedra, int(row.valid), row.kinds, row.failing, *flips,
            -1 if row.rounds is None else row.rounds,
            -1 if row.tetrahedra_improved is None else row.tetrahedra_improved,
            -1 if row.valid_improved is None else int(row.valid_improved),
            -1 if row.failing_improved is None else row.failing_improved)


def chunk_rows(job: CensusJob, chunk: Chunk) -> RowArray:
    """The rows of ``chunk`` as a (patterns, 12) int32 array (what a worker computes and
    sends back)."""
    # an array, not a list: Dask serialises a list item by item, one frame per int
    # (0.6 s for the 15,000 ints of 1,251 patterns), an array as one buffer
    return np.array(_chunk_values(job, chunk), dtype=np.int32).reshape(-1, ROW_WIDTH)


def _chunk_values(job: CensusJob, chunk: Chunk) -> list[int]:
    if job.resolved_engine() == "compiled":
        if chunk.patterns is None:
            return compiled.compiled_rows(
                chunk.start, chunk.stop, job.box, order=job.order, template=job.template,
                improve=job.improve, allow_boundary_flips=job.allow_boundary_flips)
        values: list[int] = []
        for pattern in chunk:
            run = compiled.run_compiled(pattern, job.box, order=job.order,
                                        template=job.template, improve=job.improve,
                                        allow_boundary_flips=job.allow_boundary_flips)
            values.extend(row_values(run.row))
        return values
    values = []
    for pattern in chunk:
        values.extend(row_values(census_row(
            pattern, job.box, order=job.order, template=job.template, improve=job.improve,
            allow_boundary_flips=job.allow_boundary_flips)))
    return values


def rows_of_values(job: CensusJob, chunk: Chunk,
                   values: RowArray | Sequence[int]) -> list[CensusRow]:
    """The :class:`CensusRow` s of a chunk's rows (its array, or its row ints flat)."""
    order = check_order(job.order)
    shape = job.shape
    listed: list[list[int]] = np.asarray(values, dtype=np.int32).reshape(-1, ROW_WIDTH).tolist()
    return [compiled.row_of(row, pattern, shape, order, job.template)
            for row, pattern in zip(listed, chunk, strict=True)]


def _default_chunk(job: CensusJob, total: int, workers: int) -> int:
    if job.resolved_engine() == "reference":
        return 16
    # a few chunks per worker for balance, each big enough that sending it costs nothing
    return max(64, min(8192, total // max(1, 8 * workers) + 1))


def run_census(
    patterns: range | Sequence[int],
    job: CensusJob,
    *,
    workers: int | None = None,
    dask_address: str | None = None,
    chunk_size: int | None = None,
    on_progress: ProgressCallback | None = None,
) -> list[CensusRow]:
    """The census rows of ``patterns`` (in their order): in this process when ``workers``
    is 1, on a process pool of ``workers`` (default: every core), or on the Dask cluster
    at ``dask_address`` (``workers`` is then ignored: the chunks are sized for the
    cluster's threads)."""
    check_order(job.order)
    check_template(job.template)
    for pattern in (patterns if not isinstance(patterns, range) else ()):
        check_pattern(pattern)
    if isinstance(patterns, range) and len(patterns):
        check_pattern(patterns[0])
        check_pattern(patterns[-1])
    if workers is not None and workers < 1:
        raise PreconditionError("census", f"--workers must be >= 1, not {workers}")
    total = len(patterns)
    done = 0

    def progressed(chunk: Chunk) -> None:
        nonlocal done
        done += len(chunk)
        if on_progress is not None:
            on_progress(done, total)

    def chunked(count: int) -> list[Chunk]:
        return chunks_of(patterns, chunk_size or _default_chunk(job, total, count))

    if dask_address is not None:
        chunks, results = _on_dask(dask_address, job, chunked, progressed)
    else:
        count = workers or os.cpu_count() or 1
        chunks = chunked(count)
        if count == 1 or len(chunks) <= 1:
            results = []
            for chunk in chunks:
                results.append(chunk_rows(job, chunk))
                progressed(chunk)
        else:
            results = _on_pool(count, job, chunks, progressed)
    rows: list[CensusRow] = []
    for chunk, values in zip(chunks, results, strict=True):
        rows.extend(rows_of_values(job, chunk, values))
    return rows


def _on_pool(workers: int, job: CensusJob, chunks: list[Chunk],
             progressed: Callable[[Chunk], None]) -> list[RowArray]:
    results: list[RowArray | None] = [None] * len(chunks)
    with ProcessPoolExecutor(max_workers=min(workers, len(chunks))) as pool:
        futures: dict[Future[RowArray], int] = {
            pool.submit(chunk_rows, job, chunk): index for index, chunk in enumerate(chunks)
        }
        waiting = set(futures)
        while waiting:
            finished, waiting = wait(waiting, return_when=FIRST_COMPLETED)
            for future in sorted(finished, key=futures.__getitem__):
                index = futures[future]
                results[index] = future.result()
                progressed(chunks[index])
    return [values for values in results if values is not None]


def _distributed() -> Any:
    try:
        distributed = importlib.import_module("distributed")
    except ImportError:
        raise MissingDependencyError("dask[distributed]", "the census on a Dask cluster "
                                     "(--dask)", "cluster") from None
    return distributed


def _on_dask(address: str, job: CensusJob, chunked: Callable[[int], list[Chunk]],
             progressed: Callable[[Chunk], None]) -> tuple[list[Chunk], list[RowArray]]:
    distributed = _distributed()
    with distributed.Client(address, set_as_default=False) as client:
        threads = sum(client.nthreads().values()) or 1
        chunks = chunked(threads)
        results: list[RowArray | None] = [None] * len(chunks)
        futures = client.map(chunk_rows, [job] * len(chunks), chunks, pure=False)
        index_of = {future.key: index for index, future in enumerate(futures)}
        for future in distributed.as_completed(futures, loop=client.loop):
            index = index_of[future.key]
            results[index] = future.result()
            progressed(chunks[index])
    return chunks, [values for values in results if values is not None]
