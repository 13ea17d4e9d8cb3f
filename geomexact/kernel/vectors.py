"""Space vectors as plain triples of numbers (typed for ints or floats): difference, cross
product and dot product, in the numbers' own arithmetic (exact for exact numbers)."""

from __future__ import annotations

from typing import TypeVar

__all__ = ["cross3", "dot3", "sub3"]

N = TypeVar("N", int, float)


def sub3(p: tuple[N, N, N], q: tuple[N, N, N]) -> tuple[N, N, N]:
    """``p - q``."""
    return (p[0] - q[0], p[1] - q[1], p[2] - q[2])


def cross3(p: tuple[N, N, N], q: tuple[N, N, N]) -> tuple[N, N, N]:
    """``p x q`` (right-handed)."""
    return (p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0])


def dot3(p: tuple[N, N, N], q: tuple[N, N, N]) -> N:
    """``p . q``."""
    return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]
