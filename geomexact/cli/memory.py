"""The memory a command may use (``--max-memory``; by default what this machine and this
process's limits allow), the estimates a command checks against it before the work, and
the address-space cap that turns a larger allocation into a one-line error (exit 2).

The estimates are measured costs per item of what a command builds (``docs/cli.md``,
"Memory budget"), each rounded up: a refusal up front costs a second, a run that dies in
a swap storm costs the machine."""

from __future__ import annotations

import contextlib
import contextvars
import os
import re
from collections.abc import Iterator
from pathlib import Path

import attrs

from geomexact.errors import GeomexactError

BYTES_PER_TRIANGLE = 1_000
"""Peak bytes per triangle of a refined 2D mesh, with its trace (measured: 700 B at
10^6 triangles; the criteria's estimates count up to 1.5 times the triangles made)."""

BYTES_PER_POINT = 3_000
"""Peak bytes per input point of a Delaunay triangulation (measured: 2,800 B at 2 × 10^5
points, with its trace)."""

BYTES_PER_TETRAHEDRON = 2_000
"""Peak bytes per tetrahedron of an octree mesh (measured: 800 B on a ball at level 5)."""

BYTES_PER_FILE_BYTE = 40
"""Peak bytes per byte of a mesh file read (measured: 20 for `info`, 28 for `check` of
a 4 MB OFF)."""

MACHINE_SHARE = 0.8
"""The share of this machine's memory a command may use by default."""

_UNITS = {"": 1, "K": 1 << 10, "M": 1 << 20, "G": 1 << 30, "T": 1 << 40}
_SIZE = re.compile(r"\s*([0-9]+(?:\.[0-9]*)?)\s*([KMGT]?)(?:i?B)?\s*", re.IGNORECASE)


class MemoryBudgetError(GeomexactError, MemoryError):
    """A command refused before the work: what it would build needs more memory than its
    budget."""


@attrs.frozen
class MemoryBudget:
    """At most ``limit`` bytes, and where that number comes from (``source``, for the
    message)."""

    limit: int
    source: str

    def refuse_beyond(self, what: str, estimate: int, hint: str) -> None:
        """:class:`MemoryBudgetError` when ``estimate`` bytes (for ``what``) exceed the
        budget; ``hint`` says how to ask for less."""
        if estimate > self.limit:
            raise MemoryBudgetError(
                f"{what} needs about {size_text(estimate)} of memory, more than the "
                f"{size_text(self.limit)} this command may use ({self.source}); {hint}, or "
                f"{self.more()}")

    def more(self) -> str:
        """How to allow more: a larger ``--max-memory``, or a larger ``ulimit -v``."""
        return ("raise the limit (ulimit -v)" if "ulimit" in self.source
                else "give a larger --max-memory")

    def items(self, bytes_per_item: int) -> int:
        """How many items of ``bytes_per_item`` bytes fit in the budget."""
        return max(0, self.limit // bytes_per_item)


def size_text(size: int | float) -> str:
    """``size`` bytes as ``"1.5 GB"`` (powers of 1024)."""
    for unit, scale in (("TB", 1 << 40), ("GB", 1 << 30), ("MB", 1 << 20), ("kB", 1 << 10)):
        if size >= scale:
            return f"{size / scale:,.1f} {unit}"
    return f"{size:,.0f} bytes"


def parse_size(text: str) -> int:
    """``--max-memory``: bytes, or a number with K, M, G or T (powers of 1024): ``512M``,
    ``2.5G``; a ValueError otherwise."""
    match = _SIZE.fullmatch(text)
    if match is None:
        raise ValueError(f"{text!r} is not a size (e.g. 512M, 2G)")
    size = int(float(match.group(1)) * _UNITS[match.group(2).upper()])
    if size <= 0:
        raise ValueError(f"{text!r}: a memory budget is positive")
    return size


def _meminfo(field: str) -> int | None:
    try:
        text = Path("/proc/meminfo").read_text()
    except OSError:
        return None
    match = re.search(rf"^{field}:\s+(\d+) kB", text, re.MULTILINE)
    return int(match.group(1)) * 1024 if match else None


def _address_space() -> int:
    """This process's address space now (bytes; 0 where /proc is missing)."""
    try:
        text = Path("/proc/self/status").read_text()
    except OSError:
        return 0
    match = re.search(r"^VmSize:\s+(\d+) kB", text, re.MULTILINE)
    return int(match.group(1)) * 1024 if match else 0


def _address_space_limit() -> int | None:
    try:
        import resource
    except ImportError:  # pragma: no cover - Windows
        return None
    soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    return None if soft == resource.RLIM_INFINITY else int(soft)


def machine_budget() -> MemoryBudget:
    """The default budget: :data:`MACHINE_SHARE` of this machine's memory, no more than is
    available now, and within this process's address-space limit (``ulimit -v``)."""
    total = _meminfo("MemTotal")
    if total is None:
        pages = os.sysconf("SC_PHYS_PAGES") if hasattr(os, "sysconf") else 0
        total = pages * os.sysconf("SC_PAGE_SIZE") if pages > 0 else 1 << 34
    limit, source = int(total * MACHINE_SHARE), f"{MACHINE_SHARE:.0%} of this machine's memory"
    available = _meminfo("MemAvailable")
    if available is not None and available < limit:
        limit, source = available, "the memory available on this machine now"
    return _within_address_space_limit(MemoryBudget(limit, source))


def _within_address_space_limit(budget: MemoryBudget) -> MemoryBudget:
    """``budget``, or less when this process's address-space limit leaves less."""
    cap = _address_space_limit()
    if cap is not None and cap - _address_space() < budget.limit:
        return MemoryBudget(max(0, cap - _address_space()),
                            "what this process's address-space limit (ulimit -v) leaves")
    return budget


def budget_of(max_memory: int | None) -> MemoryBudget:
    """The budget of ``--max-memory`` (None: :func:`machine_budget`), never more than the
    address-space limit leaves."""
    if max_memory is None:
        return machine_budget()
    return _within_address_space_limit(MemoryBudget(max_memory, "--max-memory"))


def cap_address_space(budget: MemoryBudget) -> None:
    """Let this process grow by at most the budget (``RLIMIT_AS``, never above the hard
    limit): an allocation beyond it fails as a MemoryError, which the command reports in
    one line, rather than the machine swapping or the kernel killing a process."""
    try:
        import resource
    except ImportError:  # pragma: no cover - Windows
        return
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    wanted = _address_space() + budget.limit
    if hard != resource.RLIM_INFINITY:
        wanted = min(wanted, hard)
    if soft == resource.RLIM_INFINITY or wanted < soft:
        with contextlib.suppress(ValueError, OSError):
            resource.setrlimit(resource.RLIMIT_AS, (wanted, hard))


_ACTIVE: contextvars.ContextVar[MemoryBudget | None] = contextvars.ContextVar(
    "geomexact_memory_budget", default=None)


@contextlib.contextmanager
def command_budget(budget: MemoryBudget) -> Iterator[MemoryBudget]:
    """``budget`` as the running command's (:func:`active_budget`) until the block ends."""
    token = _ACTIVE.set(budget)
    try:
        yield budget
    finally:
        _ACTIVE.reset(token)


def active_budget() -> MemoryBudget:
    """The running command's budget (:func:`machine_budget` outside a command)."""
    budget = _ACTIVE.get()
    return budget if budget is not None else machine_budget()


def refuse_large_file(path: str) -> None:
    """Refuse (before reading) a file whose reading would need more than the budget."""
    try:
        size = os.stat(path).st_size
    except OSError:
        return  # the reader names what is wrong with it
    active_budget().refuse_beyond(
        f"reading {path} ({size_text(size)})", size * BYTES_PER_FILE_BYTE,
        "read a smaller file")
