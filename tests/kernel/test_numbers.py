"""The exact scalar: parsing is exact, errors name the text, printing round-trips, floats
convert to their exact binary value and back with correct rounding."""

from __future__ import annotations

import math
import sys
from fractions import Fraction

import gmpy2
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from geomexact.errors import GeomexactError, RationalParseError
from geomexact.kernel.numbers import (
    DoubleRangeError,
    approximate_text,
    format_decimal,
    format_float,
    format_rational,
    is_finite_decimal,
    mpq,
    parse_rational,
    sign,
    to_float,
    to_rational,
)

big_fractions = st.fractions().map(lambda f: mpq(f.numerator, f.denominator))
finite_floats = st.floats(allow_nan=False, allow_infinity=False)


def finite_decimals() -> st.SearchStrategy[object]:
    return st.builds(
        lambda digits, exponent: mpq(digits) * mpq(10) ** exponent,
        st.integers(-(10**30), 10**30),
        st.integers(-60, 60),
    )


# ---- parse_rational ---------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("0.1", mpq(1, 10)),
        ("1e-3", mpq(1, 1000)),
        ("-2.5E+4", mpq(-25000)),
        ("3/4", mpq(3, 4)),
        ("-6/8", mpq(-3, 4)),
        ("+3/4", mpq(3, 4)),
        (".5", mpq(1, 2)),
        ("2.", mpq(2)),
        ("-.5", mpq(-1, 2)),
        ("+.5e1", mpq(5)),
        ("+3", mpq(3)),
        ("-0", mpq(0)),
        ("007.50", mpq(15, 2)),
        ("  42\n", mpq(42)),
        ("1E5", mpq(100000)),
        ("0.1e1", mpq(1)),
        ("123456789012345678901234567890.5", mpq(246913578024691357802469135781, 2)),
        ("1e-400", mpq(1, 10**400)),
        ("1" * 5000 + "/3", mpq(int("1" * 4000) * 10**1000 + int("1" * 1000), 3)),
    ],
)
def test_parse_rational_is_exact(text: str, expected: object) -> None:
    value = parse_rational(text)
    assert value == expected
    assert isinstance(value, type(mpq(1, 2)))


@pytest.mark.parametrize(
    "text",
    [
        "nan",
        "NaN",
        "-nan",
        "inf",
        "-Infinity",
        "+inf",
        "",
        "   ",
        "abc",
        "1/0",
        "-5/000",
        "0x10",
        "1_000",
        ".",
        "e5",
        "1.5e",
        "1/-2",
        "1/2/3",
        "1 / 2",
        "--1",
        "1e1000001",
        "1e" + "9" * 5000,
        "\u0663",  # ARABIC-INDIC DIGIT THREE: only ASCII digits are numbers here
        "\u0661/\u0662",
    ],
)
def test_parse_rational_errors_name_the_text(text: str) -> None:
    with pytest.raises(RationalParseError) as caught:
        parse_rational(text)
    assert caught.value.text == text
    assert repr(text) in str(caught.value)
    assert isinstance(caught.value, ValueError)
    assert isinstance(caught.value, GeomexactError)


@given(big_fractions)
def test_format_rational_round_trips_through_parse_rational(value: object) -> None:
    assert parse_rational(format_rational(value)) == value  # type: ignore[arg-type]


@given(st.fractions())
def test_parse_rational_reads_p_over_q_exactly(value: Fraction) -> None:
    assert parse_rational(f"{value.numerator}/{value.denominator}") == value
    assert parse_rational(f" {value.numerator}/{value.denominator}\t") == value


@given(st.decimals(allow_nan=False, allow_infinity=False))
def test_parse_rational_reads_decimal_text_exactly(value: object) -> None:
    from decimal import Decimal

    assert isinstance(value, Decimal)
    text = str(value)
    if "E" in text.upper() and abs(value.adjusted()) > 100_000:
        return
    assert Fraction(parse_rational(text)) == Fraction(value)


# ---- format_decimal / format_rational ----------------------------------------------------


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (mpq(1, 8), "0.125"),
        (mpq(-3), "-3"),
        (mpq(0), "0"),
        (mpq(1, 10), "0.1"),
        (mpq(100), "100"),
        (mpq(1000), "1e3"),
        (mpq(-25000), "-25000"),  # "-2.5e4" is not shorter
        (mpq(15, 10**31), "1.5e-30"),
        (mpq(5, 2), "2.5"),
        (mpq(1, 1000), "1e-3"),
        (mpq(1, 100), "0.01"),
    ],
)
def test_format_decimal_examples(value: object, text: str) -> None:
    assert format_decimal(value) == text
    assert format_rational(value) == text


def plain_digits_needed(value: Fraction) -> int:
    """Length of the shortest positional text (no exponent) of a finite decimal."""
    places = 0
    while (value * 10**places).denominator != 1:
        places += 1
    digits = str(abs((value * 10**places).numerator))
    if places == 0:
        body = digits
    elif len(digits) > places:
        body = digits[:-places] + "." + digits[-places:]
    else:
        body = "0." + "0" * (places - len(digits)) + digits
    return len(body) + (value < 0)


@given(finite_decimals())
def test_format_decimal_is_shortest_and_exact(value: object) -> None:
    text = format_decimal(value)  # type: ignore[arg-type]
    assert parse_rational(text) == value
    assert len(text) <= plain_digits_needed(Fraction(int(value.numerator), int(value.denominator)))  # type: ignore[attr-defined]
    mantissa = text.lstrip("-").split("e")[0]
    if "." in mantissa:
        assert not mantissa.endswith("0")


@given(big_fractions)
def test_format_decimal_refuses_non_terminating_values(value: object) -> None:
    if is_finite_decimal(value):  # type: ignore[arg-type]
        assert parse_rational(format_decimal(value)) == value  # type: ignore[arg-type]
    else:
        with pytest.raises(ValueError, match="no finite decimal"):
            format_decimal(value)  # type: ignore[arg-type]
        numerator, denominator = format_rational(value).split("/")  # type: ignore[arg-type]
        assert mpq(int(numerator), int(denominator)) == value


def test_is_finite_decimal() -> None:
    assert is_finite_decimal(mpq(3, 40))
    assert is_finite_decimal(mpq(7))
    assert not is_finite_decimal(mpq(1, 3))
    assert not is_finite_decimal(mpq(1, 30))


# ---- to_rational -------------------------------------------------------------------------


@given(finite_floats)
@example(0.1)
@example(5e-324)
@example(sys.float_info.max)
@example(-0.0)
def test_to_rational_of_a_float_is_its_exact_binary_value(value: float) -> None:
    exact = to_rational(value)
    assert Fraction(int(exact.numerator), int(exact.denominator)) == Fraction(value)


def test_to_rational_examples() -> None:
    assert to_rational(0.1) == mpq(3602879701896397, 2**55)
    assert to_rational(0.1) != mpq(1, 10)
    assert to_rational("0.1") == mpq(1, 10)
    assert to_rational(Fraction(2, 6)) == mpq(1, 3)
    assert to_rational(7) == 7
    assert to_rational(gmpy2.mpz(7)) == 7
    assert to_rational(mpq(1, 3)) == mpq(1, 3)


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, True, None, 1 + 2j, object()])
def test_to_rational_refuses_non_numbers(value: object) -> None:
    with pytest.raises(RationalParseError):
        to_rational(value)


# ---- to_float ----------------------------------------------------------------------------


def nearest_double(value: Fraction) -> float:
    """Reference rounding by integer arithmetic: the double nearest to ``value`` > 0
    (below the overflow threshold), ties to even."""
    numerator, denominator = value.numerator, value.denominator
    exponent = numerator.bit_length() - denominator.bit_length()
    if Fraction(2) ** exponent > value:
        exponent -= 1  # now 2^exponent <= value < 2^(exponent + 1)
    shift = 52 - max(exponent, -1022)  # subnormals share the exponent -1022
    scaled = value * Fraction(2) ** shift
    mantissa, remainder = divmod(scaled.numerator, scaled.denominator)
    if 2 * remainder > scaled.denominator or (
        2 * remainder == scaled.denominator and mantissa % 2 == 1
    ):
        mantissa += 1
    return math.ldexp(mantissa, -shift)


rationals_any_scale = st.builds(
    lambda fraction, shift: fraction * Fraction(2) ** shift,
    st.fractions(max_denominator=10**30).filter(lambda f: f != 0),
    st.integers(-1100, 1000),
)


@given(rationals_any_scale)
@example(Fraction(1, 10))
@example(Fraction(3, 2**1075))  # subnormal halfway cases round to even
@example(Fraction(1, 2**1075))
@example(Fraction(2**1024 - 2**970 - 1))  # just below the overflow midpoint
def test_to_float_is_correctly_rounded(value: Fraction) -> None:
    q = mpq(value.numerator, value.denominator)
    if abs(value) >= 2**1024 - 2**970:
        with pytest.raises(OverflowError, match="beyond the range"):
            to_float(q)
        return
    result = to_float(q)
    assert result == math.copysign(nearest_double(abs(value)), value)
    assert format_float(q) == repr(result)


def test_to_float_examples() -> None:
    assert to_float(mpq(1, 10)) == 0.1
    assert to_float(mpq(1, 3)) == 1 / 3
    assert to_float(mpq(2**1024 - 2**971)) == sys.float_info.max
    assert to_float(mpq(1, 2**1080)) == 0.0
    with pytest.raises(OverflowError):
        to_float(mpq(10) ** 400)


def test_sign() -> None:
    assert sign(mpq(-1, 3)) == -1
    assert sign(mpq(0)) == 0
    assert sign(mpq(10) ** 400) == 1


@given(st.fractions(min_value=Fraction(1, 10**30), max_value=Fraction(10**30)))
def test_floor_log2_brackets_the_value(value: Fraction) -> None:
    """2^k <= value < 2^(k+1) for k = floor_log2(value), exactly."""
    from geomexact.kernel.numbers import floor_log2

    exact = mpq(value.numerator, value.denominator)
    k = floor_log2(exact)
    assert mpq(2) ** k <= exact < mpq(2) ** (k + 1)


# ---- any size (issue 11) --------------------------------------------------------------------


def test_text_of_numbers_beyond_the_int_str_digit_limit() -> None:
    """200,001 digits, 1/10^100000 and p/q with 100,000-digit parts print and read back
    exactly, fast, without touching the process's int <-> str digit limit."""
    limit = sys.get_int_max_str_digits()
    huge = mpq(3) * mpq(10) ** 200_000 + 1
    for value in (huge, -huge / 7, mpq(5, 10**100_000), mpq(1, 2**300_000),
                  mpq(4, gmpy2.mpz("7" * 100_000))):
        text = format_rational(value)
        assert parse_rational(text) == value
    assert format_rational(mpq(10) ** 200_000) == "1e200000"
    assert format_rational(mpq(-3, 10**100_000)) == "-3e-100000"
    assert sys.get_int_max_str_digits() == limit


@given(st.fractions(max_denominator=10**12), st.integers(0, 200), st.integers(0, 200))
def test_decimal_text_uses_the_least_scale(value: Fraction, twos: int, fives: int) -> None:
    """The decimal digits of p / (2^a 5^b): read back exactly, no trailing zero after the
    point."""
    q = mpq(value.numerator, value.denominator) / (mpq(2) ** twos * mpq(5) ** fives)
    if is_finite_decimal(q):
        text = format_decimal(q)
        assert parse_rational(text) == q
        assert not ("." in text and text.split("e")[0].endswith("0"))


@pytest.mark.parametrize(("value", "text"), [
    (mpq(0), "0"), (mpq(1, 10), "0.1"), (mpq(-1, 3), "-0.333333"),
    (mpq(3) * mpq(10) ** 309, "3e309"), (mpq(-1, 7) / mpq(10) ** 100_000, "-1.42857e-100001"),
    (mpq(123456789), "1.23457e8"), (mpq(10) ** 200_000 * 11 / 2, "5.5e200000"),
])
def test_approximate_text(value: object, text: str) -> None:
    assert approximate_text(value) == text


def test_beyond_the_doubles_is_one_clear_error() -> None:
    """A GeomexactError (one line from the command) and an OverflowError, naming the value
    briefly even when it has 200,001 digits."""
    with pytest.raises(DoubleRangeError) as caught:
        format_float(mpq(3) * mpq(10) ** 200_000)
    assert isinstance(caught.value, GeomexactError) and isinstance(caught.value, OverflowError)
    assert str(caught.value).startswith("3e200000 is beyond the range of a double")
    assert len(str(caught.value)) < 200
    assert caught.value.value == mpq(3) * mpq(10) ** 200_000


def test_exponents_up_to_a_million_are_read() -> None:
    assert parse_rational("2e1000000") == 2 * mpq(10) ** 1_000_000
    assert parse_rational("-1.5e-1000000") == mpq(-3, 2) / mpq(10) ** 1_000_000
    with pytest.raises(RationalParseError, match="at most 1,000,000"):
        parse_rational("1e-1000001")
