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

from geomexact.errors import DoubleRangeError, RationalParseError

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
# refuse "1e999999999" instead of allocating a huge integer; 10^1000000 (415 kB, built in
# milliseconds) is as big as a million written digits, which are accepted too
_MAX_EXPONENT = 1_000_000


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
            raise RationalParseError(
                text, f"exponent out of range (at most {_MAX_EXPONENT:,} in magnitude)"
            )
        fraction = decimal["fraction"] or ""
        digits = gmpy2.mpz((decimal["whole"] + fraction) or 0)
        exponent = int(written_exponent) - len(fraction)
        power = gmpy2.mpz(10) ** abs(exponent)  # GMP's power: 40x faster than int's here
        value = mpq(digits * power) if exponent >= 0 else mpq(digits, power)
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


def _without_twos_and_fives(denominator: Any) -> tuple[Any, int, int]:
    """``(rest, a, b)`` with ``denominator = rest * 2^a * 5^b`` and rest prime to 10.
    GMP's ``mpz_remove``: fast at any size (the digit-by-digit loop it replaces was
    quadratic, minutes for a 100,000-digit power of ten)."""
    rest, twos = gmpy2.remove(gmpy2.mpz(denominator), 2)
    rest, fives = gmpy2.remove(rest, 5)
    return rest, int(twos), int(fives)


def is_finite_decimal(value: Rational) -> bool:
    """True when ``value`` has a terminating decimal expansion (denominator 2^a 5^b)."""
    return bool(_without_twos_and_fives(value.denominator)[0] == 1)


def exact_decimal(value: Rational, *, plain_within: int = 0) -> str | None:
    """The exact decimal text of ``value`` (``1/8`` -> ``"0.125"``, ``-3`` -> ``"-3"``), or
    None when its expansion does not terminate.  The exponent form (``"1.5e-30"``) is used
    when it is shorter than the plain one by more than ``plain_within`` characters (0: the
    shortest text).  Linear in the size of the number, any size (gmpy2 writes the digits:
    no 4300-digit limit); ``parse_rational`` reads it back exactly."""
    rest, twos, fives = _without_twos_and_fives(value.denominator)
    if rest != 1:
        return None
    numerator = gmpy2.mpz(value.numerator)
    if numerator == 0:
        return "0"
    # value = digits * 10^-scale, least scale: 10^scale / (2^a 5^b) = 2^(scale-a) 5^(scale-b)
    scale = max(twos, fives)
    digits = str(abs(numerator) * gmpy2.mpz(2) ** (scale - twos) * gmpy2.mpz(5) ** (scale - fives))
    return _decimal_text(numerator < 0, digits, scale, plain_within)


_FIVE = gmpy2.mpz(5)


def dyadic_decimal(value: Rational, *, plain_within: int = 0) -> str | None:
    """:func:`exact_decimal` of ``value`` when its denominator is a power of two (an
    integer, a midpoint, a grid coordinate: the common case of a writer), else None.
    Cheaper: no factoring of the denominator (``value = n / 2^k`` is ``n 5^k / 10^k``)."""
    denominator = value.denominator
    if denominator & (denominator - 1):
        return None
    numerator = gmpy2.mpz(value.numerator)
    if not numerator:
        return "0"
    scale = denominator.bit_length() - 1
    digits = str(abs(numerator) * _FIVE**scale if scale else abs(numerator))
    return _decimal_text(numerator < 0, digits, scale, plain_within)


def _decimal_text(negative: bool, digits: str, scale: int, plain_within: int) -> str:
    """The text of ``±digits * 10^-scale`` (digits without leading zeros): plain, or in
    exponent form when that is shorter by more than ``plain_within`` characters."""
    sign = "-" if negative else ""
    significant = digits.rstrip("0")
    plain: str
    if scale == 0:
        plain = digits
    elif len(digits) > scale:
        plain = f"{digits[:-scale]}.{digits[-scale:]}"
    else:
        plain = "0." + "0" * (scale - len(digits)) + digits
    exponent = len(digits) - 1 - scale
    mantissa = significant[0] + ("." + significant[1:] if len(significant) > 1 else "")
    scientific = f"{mantissa}e{exponent}"
    return sign + (scientific if len(scientific) + plain_within < len(plain) else plain)


def format_decimal(value: Rational) -> str:
    """The shortest exact decimal text of a finite decimal (:func:`exact_decimal`);
    ``ValueError`` when ``value`` is not one."""
    text = exact_decimal(value)
    if text is None:
        raise ValueError(f"{approximate_text(value)} has no finite decimal expansion")
    return text


def format_rational(value: Rational) -> str:
    """Exact text of ``value``: the shortest decimal when it terminates, else ``"p/q"``.
    Any size."""
    if is_finite_decimal(value):
        return format_decimal(value)
    return f"{gmpy2.mpz(value.numerator)}/{gmpy2.mpz(value.denominator)}"


def approximate_text(value: Rational, digits: int = 6) -> str:
    """``value`` rounded to ``digits`` significant digits as short text, at any magnitude
    (``"0.1"``, ``"3e309"``, ``"-1.42857e-100001"``): for messages, where the exact text
    could be millions of digits long; never for data."""
    if value == 0:
        return "0"
    with gmpy2.context(precision=4 * digits + 16):
        text = f"{gmpy2.mpfr(value):.{digits}g}"
    mantissa, _, exponent = text.partition("e")
    return f"{mantissa}e{int(exponent)}" if exponent else mantissa


def format_float(value: Rational) -> str:
    """Text of the double nearest to ``value`` (Python ``repr``), for float-only formats.

    Raises :class:`DoubleRangeError` (an ``OverflowError``) for values beyond the double
    range.
    """
    return repr(to_float(value))


def double_range_error(value: Rational) -> DoubleRangeError:
    """The error for ``value``, whose nearest double would be infinite."""
    return DoubleRangeError(
        f"{approximate_text(value)} is beyond the range of a double (about 1.8e308): "
        "it can only be written exactly (exact=True, --exact)",
        value,
    )


def to_float(value: Rational) -> float:
    """The double nearest to ``value`` (ties to even), raising :class:`DoubleRangeError`
    (an ``OverflowError``) when it would be infinite."""
    numerator, denominator = int(value.numerator), int(value.denominator)
    try:
        return numerator / denominator  # Python's int/int division is correctly rounded
    except OverflowError:
        raise double_range_error(value) from None


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
