"""Printing a command's report: one JSON object on stdout, or a titled table of rows."""

from __future__ import annotations

import json
from collections.abc import Iterable
from typing import Any

from geomexact.errors import Violation


def print_json(report: dict[str, Any]) -> None:
    """Print ``report`` as one indented JSON object (no NaN or infinity)."""
    print(json.dumps(report, indent=2, allow_nan=False))


def _show(value: object) -> str:
    """A report value as table text (JSON keeps the value itself)."""
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, dict) and set(value) == {"x_min", "x_max", "y_min", "y_max"}:
        return f"x {value['x_min']} .. {value['x_max']}, y {value['y_min']} .. {value['y_max']}"
    if isinstance(value, dict):  # counts by name, e.g. cells by kind
        return ", ".join(f"{key} {count}" for key, count in value.items()) or "-"
    if isinstance(value, list):
        return ", ".join(map(str, value)) or "-"
    return str(value)


def print_table(title: str, rows: dict[str, Any]) -> None:
    """Print ``title``, then one aligned ``key  value`` line per row (``_`` in keys shown
    as spaces)."""
    print(title)
    width = max((len(key) for key in rows), default=0)
    for key, value in rows.items():
        print(f"  {key.replace('_', ' '):<{width}}  {_show(value)}")


def violation_reports(violations: Iterable[Violation]) -> list[dict[str, Any]]:
    """The JSON ``violations`` list: ``kind``, ``message`` and ``elements`` of each."""
    return [{"kind": v.kind, "message": v.message, "elements": list(v.elements)}
            for v in violations]
