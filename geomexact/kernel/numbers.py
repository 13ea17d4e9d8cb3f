"""The exact scalar of geomexact: gmpy2 ``mpq`` rationals, exact parsing and printing.

Every coordinate in the package is an :data:`Rational` (``gmpy2.mpq``).  Text is parsed
exactly (``"0.1"`` is 1/10, never the double nearest to 0.1); a Python ``float`` converts to
its exact binary value.  This module is the only place that turns text or floats into
coordinates and coordinates into text.  See ``specs/numbers.md``.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from typing import Any, TypeAlias

import gmpy2

from geomexact.errors import RationalParseError

Rational: TypeAlias = "gmpy2.mpq"
mpq = gmpy2.mpq

ZERO = mpq(0)
ONE = mpq(1)
HALF = mpq(1, 2)

# decimal: optional sign, digits with optional fraction (or fraction alone), optional exponent.
# ASCII digits only; the groups are assembled into an integer here (gmpy2's own decimal
# parser rejects "+3" and "-.5", and Python's int() refuses more than 4300 digits).
_DECIMAL = re.compile(
    r"(?P<sign>[+-]?)(?P<whole>\d*)(?:\.(?P<fraction>\d*))?(?:[eE](?P<exponent>[+-]?\d+))?",
    re.ASCII,
)
_FRACTION = re.compile(r"(?P<numerator>[+-]?\d+)/(?P<denominator>\d+)", re.ASCII)
_MAX_EXPONENT = 100_000  # refuse "1e999999999" instead of allocating a huge integer


def parse_rational(text: str) -> Rational:
    """Parse ``text`` exactly into a rational.

    Accepts integers (``"-3"``), decimals (``"0.1"``, ``".5"``, ``"2."``), scientific
    notation (``"1e-3"``, ``"-2.5E+4"``) and fractions (``"p/q"``, q > 0); surrounding
    whitespace is ignored.  Raises :class:`RationalParseError` (a ``ValueError``) naming the
    text for anything else: NaN, infinities, empty text, ``1/0``, hexadecimal, garbage.
    """
    stripped = text.strip()
    decimal = _DECIMAL.fullmatch(stripped)
    if decimal and (decimal["whole"] or decimal["fraction"]):
        written_exponent = gmpy2.mpz(decimal["exponent"] or 0)
        if abs(written_exponent) > _MAX_EXPONENT:
            raise RationalParseError(text, "exponent out of range")
        fraction = decimal["fraction"] or ""
        digits = gmpy2.mpz((decimal["whole"] + fraction) or 0)
        exponent = int(written_exponent) - len(fraction)
        value = mpq(digits * 10**exponent) if exponent >= 0 else mpq(digits, 10**-exponent)
        return -value if decimal["sign"] == "-" else value
    fraction_match = _FRACTION.fullmatch(stripped)
    if fraction_match:
        denominator = gmpy2.mpz(fraction_match["denominator"])
        if denominator == 0:
            raise RationalParseError(text, "zero denominator")
        return mpq(gmpy2.mpz(fraction_match["numerator"]), denominator)
    lowered = stripped.lower()
    if lowered in {"nan", "+nan", "-nan"}:
        raise RationalParseError(text, "NaN is not a number geomexact can use")
    if lowered.lstrip("+-") in {"inf", "infinity"}:
        raise RationalParseError(text, "infinity is not a coordinate")
    raise RationalParseError(text, "not a number (expected integer, decimal or p/q)")


def to_rational(value: object) -> Rational:
    """Convert ``value`` exactly: ``int``, ``mpq``, ``mpz``, ``fractions.Fraction``, ``str``
    (parsed by :func:`parse_rational`) or a finite ``float`` (its exact binary value)."""
    if isinstance(value, str):
        return parse_rational(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise RationalParseError(repr(value), "not a finite float")
        return mpq(value)
    if isinstance(value, bool):
        raise RationalParseError(repr(value), "a bool is not a coordinate")
    try:
        return mpq(value)
    except (TypeError, ValueError) as error:
        raise RationalParseError(repr(value), f"cannot convert {type(value).__name__}") from error


def is_finite_decimal(value: Rational) -> bool:
    """True when ``value`` has a terminating decimal expansion (denominator 2^a 5^b)."""
    denominator = int(value.denominator)
    for prime in (2, 5):
        while denominator % prime == 0:
            denominator //= prime
    return denominator == 1


def format_decimal(value: Rational) -> str:
    """Shortest decimal text of a finite decimal (``1/8`` -> ``"0.125"``, ``-3`` -> ``"-3"``).

    Raises ``ValueError`` when ``value`` is not a finite decimal.  Long expansions use an
    exponent (``"1.5e-30"``) when that is shorter.  ``parse_rational`` reads it back exactly.
    """
    if not is_finite_decimal(value):
        raise ValueError(f"{value} has no finite decimal expansion")
    numerator, denominator = int(value.numerator), int(value.denominator)
    sign = "-" if numerator < 0 else ""
    numerator = abs(numerator)
    # value = numerator / denominator = digits * 10^-scale with the least scale
    scale = 0
    while denominator != 1:
        if denominator % 10 == 0:
            denominator //= 10
        elif denominator % 2 == 0:
            denominator //= 2
            numerator *= 5
        else:
            denominator //= 5
            numerator *= 2
        scale += 1
    digits = str(numerator)
    trailing = len(digits) - len(digits.rstrip("0")) if numerator else 0
    plain: str
    if scale == 0:
        plain = digits
    elif len(digits) > scale:
        plain = f"{digits[:-scale]}.{digits[-scale:]}"
    else:
        plain = "0." + "0" * (scale - len(digits)) + digits
    significant = digits[: len(digits) - trailing] if trailing else digits
    exponent = len(digits) - 1 - scale
    if numerator == 0:
        return "0"
    mantissa = significant[0] + ("." + significant[1:] if len(significant) > 1 else "")
    scientific = f"{mantissa}e{exponent}"
    return sign + (scientific if len(scientific) < len(plain) else plain)


def format_rational(value: Rational) -> str:
    """Exact text of ``value``: the shortest decimal when it terminates, else ``"p/q"``."""
    if is_finite_decimal(value):
        return format_decimal(value)
    return f"{int(value.numerator)}/{int(value.denominator)}"


def format_float(value: Rational) -> str:
    """Text of the double nearest to ``value`` (Python ``repr``), for float-only formats.

    Raises ``OverflowError`` for values beyond the double range.
    """
    return repr(to_float(value))


def to_float(value: Rational) -> float:
    """The double nearest to ``value`` (ties to even), raising ``OverflowError`` when it
    would be infinite."""
    numerator, denominator = int(value.numerator), int(value.denominator)
    try:
        return numerator / denominator  # Python's int/int division is correctly rounded
    except OverflowError as error:
        raise OverflowError(f"{value} is beyond the range of a double") from error


def floor_log2(value: Rational) -> int:
    """floor(log2(value)) of a rational value > 0, exactly."""
    numerator, denominator = int(value.numerator), int(value.denominator)
    k = numerator.bit_length() - denominator.bit_length()
    if k >= 0:
        if numerator < denominator << k:
            k -= 1
    elif numerator << -k < denominator:
        k -= 1
    return k


def sign(value: Rational) -> int:
    """-1, 0 or 1 (of a rational or an integer)."""
    # two comparisons: about 4x faster than gmpy2.sign on an mpq (the predicates' exact path)
    return (value > 0) - (value < 0)  # type: ignore[no-any-return]


def scaled_to_integers(values: Sequence[Rational]) -> list[Any]:
    """``values`` times the lcm of their denominators: integers in the same ratios, so a
    homogeneous polynomial has the same sign on them.  Much faster to compute with than
    mpq (no gcd per operation) when the denominators are unrelated (random or centroid
    coordinates)."""
    scale = 1
    for value in values:
        denominator = value.denominator
        if denominator != 1:
            scale = gmpy2.lcm(scale, denominator)
    return [value.numerator * (scale // value.denominator) for value in values]
