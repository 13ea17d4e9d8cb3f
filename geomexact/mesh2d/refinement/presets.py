"""The rules of a refinement run, and the presets that select a paper's rules.

geomexact's defaults are deliberate choices; the presets select the rules of the programs
of two studies instead, each rule a named option that can still be overridden one by one
(``specs/refine.md``, "Presets"):

========================  ======================  ===============  ======================
rule                      geomexact (default)     ``"pineda"``     ``"mellado"``
========================  ======================  ===============  ======================
``centroid``              ``"area"``              ``"area"``       ``"vertices"``
``order``                 ``"worst-first"``       ``"worst-first"``  ``"passes"``
``second_longest_rule``   ``"bisect-second"``     ``"centroid"``   ``"bisect-second"`` (*)
``factor_stop``           ``"action"``            ``"target"``     ``"action"``
========================  ======================  ===============  ======================

* ``centroid``: the point inserted into a terminal quadrilateral (Mellado 2023, Alg. 1
  and 2: the mean of its four vertices).
* ``order``: ``"worst-first"`` pops the worst bad triangle first (a priority queue);
  ``"passes"`` refines the bad triangles of a pass in vertex-id order, and those the pass
  creates in the next one, until a pass is empty (Mellado 2023, Alg. 1 and 2: the list of
  bad triangles).
* ``second_longest_rule``: when a terminal triangle's second-longest edge is a constraint
  edge, ``"bisect-second"`` bisects that edge (Rivara & Rodríguez), ``"centroid"`` ignores
  it and inserts the centroid (Pineda 2023, Alg. 2: only the boundary terminal edge is
  special), ``"bisect-longest"`` bisects the terminal (longest) edge (Mellado 2023's
  literal rule).  (*) The literal rule does not terminate on Lake Superior at 30°–35°
  (measured: the default budget stops every run but quasi at 30° and 31°), so the
  ``"mellado"`` preset takes the nearest rule that does, ``"bisect-second"``; pass
  ``second_longest_rule="bisect-longest"`` for the literal one.
* ``factor_stop``: for an average-area factor, check the region's mean after every action
  (``"action"``) or after each refined target (``"target"``, Pineda 2023, Alg. 3).

>>> rules("mellado", order="worst-first").order
'worst-first'
>>> rules(None).second_longest_rule
'bisect-second'
"""

from __future__ import annotations

from typing import Literal, TypeAlias

import attrs

from geomexact.errors import PreconditionError, warn_deprecated

__all__ = [
    "CENTROIDS",
    "FACTOR_STOPS",
    "ORDERS",
    "PRESETS",
    "SECOND_LONGEST_RULES",
    "Rules",
    "rules",
]

CentroidKind: TypeAlias = Literal["area", "area-exact", "vertices", "midpoint"]
Order: TypeAlias = Literal["worst-first", "passes"]
SecondLongestRule: TypeAlias = Literal["bisect-second", "centroid", "bisect-longest"]
FactorStop: TypeAlias = Literal["action", "target"]
Preset: TypeAlias = Literal["pineda", "mellado"]

CENTROIDS: tuple[str, ...] = ("area", "area-exact", "vertices", "midpoint")
ORDERS: tuple[str, ...] = ("worst-first", "passes")
SECOND_LONGEST_RULES: tuple[str, ...] = ("bisect-second", "centroid", "bisect-longest")
FACTOR_STOPS: tuple[str, ...] = ("action", "target")


@attrs.frozen(slots=True)
class Rules:
    """The rules of one run (module docstring)."""

    centroid: CentroidKind = "area"
    order: Order = "worst-first"
    second_longest_rule: SecondLongestRule = "bisect-second"
    factor_stop: FactorStop = "action"
    preset: Preset | None = attrs.field(default=None, eq=False)
    """The preset these rules start from (recorded in a trace's parameters), None for
    geomexact's; not part of the rules' equality."""

    def changed(self) -> dict[str, str]:
        """The rules that differ from geomexact's defaults, by name."""
        default = Rules()
        return {
            name: getattr(self, name)
            for name in ("centroid", "order", "second_longest_rule", "factor_stop")
            if getattr(self, name) != getattr(default, name)
        }


PRESETS: dict[str, Rules] = {
    "pineda": Rules(second_longest_rule="centroid", factor_stop="target", preset="pineda"),
    "mellado": Rules(centroid="vertices", order="passes",
                     second_longest_rule="bisect-second", preset="mellado"),
}
"""The rules of each paper's program."""


def _check(name: str, value: str, choices: tuple[str, ...]) -> None:
    if value not in choices:
        raise PreconditionError("refine", f"unknown {name} {value!r}; choose from {choices}")


CONSTRAINT_MIDPOINTS_NOW = ("second_longest_rule='bisect-second' (for True) or 'centroid' "
                            "(for False)")
"""What replaces the deprecated ``constraint_midpoints`` argument."""


def rules(
    preset: str | None,
    *,
    centroid: str | None = None,
    order: str | None = None,
    second_longest_rule: str | None = None,
    factor_stop: str | None = None,
    constraint_midpoints: bool | None = None,
    stacklevel: int = 2,
) -> Rules:
    """The rules of ``preset`` (None: geomexact's), with each rule given overriding it.
    ``constraint_midpoints`` is the older name of ``second_longest_rule`` ``"bisect-second"``
    (True) or ``"centroid"`` (False), deprecated (the warning points ``stacklevel`` frames
    up, as :func:`warnings.warn`'s: this function's caller by default); giving both
    differently is refused."""
    if constraint_midpoints is not None:
        warn_deprecated("constraint_midpoints", CONSTRAINT_MIDPOINTS_NOW,
                        stacklevel=stacklevel)
    if preset is not None and preset not in PRESETS:
        raise PreconditionError(
            "refine", f"unknown preset {preset!r}; choose from {tuple(PRESETS)}"
        )
    base = PRESETS[preset] if preset is not None else Rules()
    if constraint_midpoints is not None:
        implied = "bisect-second" if constraint_midpoints else "centroid"
        if second_longest_rule is not None and second_longest_rule != implied:
            raise PreconditionError(
                "refine", f"constraint_midpoints={constraint_midpoints} contradicts "
                f"second_longest_rule={second_longest_rule!r}"
            )
        second_longest_rule = implied
    changes: dict[str, str] = {}
    for name, value, choices in (
        ("centroid", centroid, CENTROIDS),
        ("order", order, ORDERS),
        ("second_longest_rule", second_longest_rule, SECOND_LONGEST_RULES),
        ("factor_stop", factor_stop, FACTOR_STOPS),
    ):
        if value is not None:
            _check(name, value, choices)
            changes[name] = value
    return attrs.evolve(base, preset=preset, **changes)  # type: ignore[arg-type]
