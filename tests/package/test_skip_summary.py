"""The suite ends with one line saying what was skipped and why (issue 26, item 4)."""

from __future__ import annotations

from conftest import skip_summary


def test_reasons_are_grouped_commonest_first() -> None:
    reasons = ["Skipped: slow: run with --runslow"] * 3 + [
        "Skipped: shared test data not found at ../shared/data",
        "could not import 'triangle': No module named 'triangle'",
        "needs a headless chromium on PATH", "Skipped: not a triangle mesh"]
    assert skip_summary(reasons) == (
        "skipped 7: 3 slow (run with --runslow), 1 a missing optional package, "
        "1 no ../shared/data, 1 no chromium, 1 not a triangle mesh")
