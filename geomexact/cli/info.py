"""``geomexact info``: statistics of meshes, PSLGs and polygon meshes."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from geomexact.cli.arguments import (
    Subcommands,
    add_command,
    add_reading_options,
)
from geomexact.cli.errors import UsageProblem
from geomexact.cli.exit_codes import EXIT_OK
from geomexact.cli.loading import Loaded, load, material_cells, surface_instead
from geomexact.cli.reporting import print_json, print_table
from geomexact.cli.summaries import materials_summary, summary_of, surface_summary
from geomexact.errors import FormatError
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3


def materials_report(loaded: Loaded) -> dict[str, Any]:
    """``material_array`` (the array's name) and ``materials`` (per id: cells, exact
    volume) of a 3D mesh file with a material cell array; else nothing."""
    found = material_cells(loaded)
    if found is None:
        return {}
    mesh = loaded.value
    assert isinstance(mesh, Mesh3 | MixedMesh3)
    name, materials = found
    return {"material_array": name, "materials": materials_summary(mesh, materials)}


def print_materials(report: dict[str, Any]) -> None:
    """One line per material of a :func:`materials_report` (none without one)."""
    for material, row in report.get("materials", {}).items():
        print(f"  material {material}: {row['cells']} cells, volume {row['volume']}")


def _describe(loaded: Loaded) -> dict[str, Any]:
    return {
        "file": loaded.path,
        "format": loaded.format,
        "kind": loaded.kind,
        **summary_of(loaded.value),
        **materials_report(loaded),
        "notes": list(loaded.notes),
    }


def _report(path: str, format: str | None, verbose: bool) -> dict[str, Any]:
    """A file's report: a mesh's, or a triangulated surface's (a 3D OBJ, STL, PLY, OFF)."""
    try:
        return _describe(load(path, format, verbose))
    except (FormatError, UsageProblem) as error:
        surface = surface_instead(path, format, error)
        if surface is None:
            raise
        return {"file": path, "format": Path(path).suffix.lower().lstrip("."),
                "kind": "triangle_surface", **surface_summary(surface), "notes": []}


def command_info(args: argparse.Namespace) -> int:
    """Statistics of each file."""
    reports = [_report(path, args.format, args.verbose) for path in args.files]
    if args.json:
        print_json(reports[0] if len(reports) == 1 else {"files": reports})
        return EXIT_OK
    for index, report in enumerate(reports):
        if index:
            print()
        rows = {k: v for k, v in report.items()
                if k not in {"file", "format", "kind", "notes", "materials"}}
        kind = report["kind"].replace("_", " ")
        print_table(f"{report['file']} ({report['format']}, {kind})", rows)
        print_materials(report)
    return EXIT_OK


def add_parser(commands: Subcommands) -> None:
    """Add the ``info`` command."""
    info = add_command(commands, "info", command_info)
    info.add_argument("files", nargs="+", metavar="FILE", help="mesh, PSLG or polygon mesh file")
    add_reading_options(info)
