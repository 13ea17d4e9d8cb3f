"""Writing a command's output files."""

from __future__ import annotations

from pathlib import Path

from geomexact import io
from geomexact.cli.errors import UsageProblem
from geomexact.cli.kinds import Value, kind_name


def write(
    path: str | Path, value: Value, format: str | None, *, overwrite: bool, exact: bool
) -> list[Path]:
    """:func:`io.write`, refusing first (exit 2) a format that cannot hold ``value``."""
    name = format or io.detect_format(path)
    kinds = io.FORMATS[name].kinds
    if not isinstance(value, kinds):
        held = " or ".join(kind_name(kind).replace("_", " ") for kind in kinds)
        kind = kind_name(type(value)).replace("_", " ")
        raise UsageProblem(f"{path}: the {name} format holds a {held}, not a {kind}")
    return io.write(path, value, format=name, overwrite=overwrite, exact=exact)
