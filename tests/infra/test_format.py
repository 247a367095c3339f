"""validate.format: significant digits, per cent and value ± uncertainty tied to the uncertainty."""

from __future__ import annotations

import pytest

from validate.errors import ValidateError
from validate.format import decimals_for, fmt_quantity, pct, pct_fixed, pm, round_sigma, sig, sigma_digits


@pytest.mark.parametrize(("x", "n", "text"), [
    (0.012345, 2, "0.012"), (0.123456, 3, "0.123"), (1.234e-5, 3, "1.23e-5"), (2.5e7, 3, "2.5e7"),
    (1234.4, 3, "1234"), (999.9, 3, "1000"), (42, 3, "42"), (0.0, 3, "0"), (-0.5, 3, "-0.5"),
    (float("nan"), 3, "NaN"), (float("inf"), 3, "∞"), (None, 3, "—"), ("text", 3, "text"),
])
def test_sig(x, n, text):
    assert sig(x, n) == text


def test_pct_is_a_drop_in_for_the_experiments_pct():
    assert pct(0.0086) == "0.86 %" and pct(0.01) == "1 %" and pct(0.125, 2) == "12 %"
    assert pct(None) == "—" and pct(float("nan")) == "—"
    # where f"{100x:.3g}" wrote "3.99e+21 %", the exponent is written plainly
    assert pct(3.99e19) == "3.99e21 %"
    assert pct_fixed(0.0086) == "0.86 %" and pct_fixed(0.5, 0) == "50 %" and pct_fixed(None) == "n/a"


@pytest.mark.parametrize(("sigma", "digits", "rounded"), [
    # PDG rule on the leading three digits: 100–354 → 2, 355–949 → 1, 950–999 → 1000 with 2
    (0.00067, 1, 0.0007), (0.0234, 2, 0.023), (0.354, 2, 0.35), (0.355, 1, 0.4), (0.949, 1, 0.9),
    (0.95, 2, 1.0), (0.0097, 2, 0.010), (0.0001, 2, 0.0001), (67.0, 1, 70.0),
])
def test_sigma_rounding(sigma, digits, rounded):
    assert sigma_digits(sigma) == digits
    assert round_sigma(sigma) == pytest.approx(rounded, rel=1e-12)


@pytest.mark.parametrize(("args", "text"), [
    ((0.012345, 0.00067, "%"), "1.23 ± 0.07 %"),  # the case
    ((9.87654, 0.0234), "9.877 ± 0.023"),
    ((3.14159, 0.36), "3.1 ± 0.4"),  # no more digits than σ supports
    ((1.2, 0.07), "1.20 ± 0.07"),  # the trailing zero is significant
    ((123.456, 0.95), "123.5 ± 1.0"),  # σ rounds up to the next decade and keeps two digits
    ((12345.6, 67.0), "12350 ± 70"),  # rounded to tens
    ((2.3e-6, 1.1e-6), "(2.3 ± 1.1)e-6"),  # shared exponent below the 10⁻⁴ place
    ((5e6, 2e5), "(5.00 ± 0.20)e6"),
    ((-0.02, 0.0012, "%"), "-2.00 ± 0.12 %"),
    ((0.5, 0.0), "0.5"), ((0.5, None, "sr"), "0.5 sr"),  # deterministic figures: the value alone
    ((2.0, 0.013, "mm", 1000.0), "2000 ± 13 mm"),  # scale for display units
])
def test_pm(args, text):
    assert pm(*args) == text


def test_pm_rejects_a_negative_uncertainty():
    with pytest.raises(ValidateError, match="uncertainty -0.1"):
        pm(1.0, -0.1)


def test_fmt_quantity():
    assert fmt_quantity(0.5, "sr") == "0.5 sr"
    assert fmt_quantity(0.01, "%") == "1 %"
    assert fmt_quantity(0.012345, "%", 0.00067) == "1.23 ± 0.07 %"
    assert fmt_quantity(None, "sr") == "—"
    assert decimals_for(0.00067) == 4 and decimals_for(67.0) == -1
