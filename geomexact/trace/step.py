"""The :class:`Step` value: one pure operation on a mesh, named with its arguments.

A step's arguments are vertex ids (``int``) and exact coordinates (``mpq``), nothing else,
so a step serialises exactly (see ``specs/trace.md``).  ``geomexact.mesh2d.ops.apply`` is the only
way a step changes a mesh.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TypeAlias

import attrs

from geomexact.kernel.numbers import Rational

StepArgument: TypeAlias = "int | Rational"


def _arguments(values: Iterable[StepArgument]) -> tuple[StepArgument, ...]:
    return tuple(values)


@attrs.frozen(slots=True)
class Step:
    """Operation ``op`` (a name registered in :data:`geomexact.mesh2d.ops.OPERATIONS`) applied
    with ``args`` (ints and rationals, in the op's documented order)."""

    op: str
    args: tuple[StepArgument, ...] = attrs.field(converter=_arguments)

    def __str__(self) -> str:
        return f"{self.op}({', '.join(str(a) for a in self.args)})"
