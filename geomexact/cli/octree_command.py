"""The pieces of ``geomexact octree`` that its box, domain and device forms share: the
box of ``--box``, the degrees argument type, the control volumes (or a usage problem)
and the report's last keys."""

from __future__ import annotations

import argparse
import resource
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from geomexact.cli.errors import UsageProblem
from geomexact.kernel.numbers import format_rational, parse_rational
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3

__all__ = ["box_of_arguments", "control_volumes_or_refuse", "degrees_below", "run_report"]


def degrees_below(bound: float, meaning: str) -> Callable[[str], float]:
    """An argparse type: a number of degrees strictly between 0 and ``bound``."""

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a number of degrees") from None
        if not 0 < value < bound:
            raise argparse.ArgumentTypeError(f"{meaning} is between 0 and {bound:g} degrees, "
                                             f"not {text}")
        return value

    return parse

def run_report(mesh: Any, trace: Any, seconds: dict[str, float], started: float,
               written: list[Path], volumes: Any) -> dict[str, Any]:
    """The keys every octree run reports last: digest, steps, stage and whole seconds,
    peak memory, the files written, the control volumes."""
    return {
        "digest": mesh.digest_text,
        "steps": None if trace is None else len(trace),
        "stage_seconds": {name: round(value, 4) for name, value in seconds.items()},
        "seconds": round(time.perf_counter() - started, 4),
        "peak_memory_mb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1),
        "written": [str(path) for path in written],
        "voronoi": None if volumes is None else {
            "vertices": len(volumes.volumes), "faces": len(volumes.faces),
            "inadequate_faces": len(volumes.inadequate_edges()),
            "total": format_rational(volumes.total)},
    }

def control_volumes_or_refuse(mesh: Mesh3 | MixedMesh3) -> Any:
    """The mesh's Voronoi control volumes; a mesh the exact check finds not Delaunay is
    a usage problem (exit 2, nothing written)."""
    from geomexact.errors import PreconditionError
    from geomexact.mesh3d.voronoi import control_volumes

    try:
        return control_volumes(mesh)
    except PreconditionError as error:
        raise UsageProblem(
            f"--voronoi: {error.problem}; nothing was written (--final polyhedral is "
            "Delaunay when the leaves are cubes, and so is any final of an octree refined "
            "to one level everywhere, without --refine-sphere or --refine-box)"
        ) from None


def box_of_arguments(args: argparse.Namespace) -> Any:
    """The box of ``--box`` (the unit cube when not given); exit 2 for an empty one."""
    from geomexact.mesh3d.cuboid.boxes import Box

    values = args.box if args.box is not None else [parse_rational(v) for v in "000111"]
    if not all(values[a] < values[a + 3] for a in range(3)):
        raise UsageProblem("--box X0 Y0 Z0 X1 Y1 Z1 needs X0 < X1, Y0 < Y1 and Z0 < Z1")
    return Box(values[:3], values[3:])
