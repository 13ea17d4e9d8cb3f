"""The exact cos^2 table of ``kernel.angles`` (Niven's theorem) agrees with sympy on every
integer degree and on a sample of fractions: the table is exactly where cos^2 is
rational."""

from __future__ import annotations

import random

import pytest

from geomexact.kernel.angles import _cos2_exact
from geomexact.kernel.numbers import mpq

sympy = pytest.importorskip("sympy")


def _sympy_cos2(degrees: object) -> object:
    value = sympy.cos(sympy.pi * sympy.Rational(str(degrees)) / 180) ** 2
    return mpq(int(value.p), int(value.q)) if value.is_Rational else None


def test_every_integer_degree() -> None:
    for degrees in range(-360, 361):
        assert _cos2_exact(mpq(degrees)) == _sympy_cos2(degrees), degrees


def test_fractions_of_a_degree() -> None:
    rng = random.Random(25)
    for _ in range(200):
        degrees = mpq(rng.randint(-720, 720), rng.randint(1, 12))
        assert _cos2_exact(degrees) == _sympy_cos2(degrees), degrees
