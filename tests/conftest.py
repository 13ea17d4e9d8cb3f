"""Shared test set-up: hypothesis profiles, the ``../shared/data`` fixture, the ``slow``
marker, and the headless Chromium plugin (``helpers.chromium``: the ``browser`` fixture
and marker).

Hypothesis profile: ``ci`` (fewer examples, no deadline) when the environment has
``CI=true``, else ``dev`` (default number of examples, no deadline: exact arithmetic on
large denominators has no fixed time budget).  ``HYPOTHESIS_PROFILE=name`` chooses one
explicitly.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import pytest
from hypothesis import settings

# explicit parent: without it a profile inherits whatever is loaded now, and hypothesis
# itself loads a built-in "ci" profile whenever a CI variable is set (even CI=false)
_base = settings.get_profile("default")
settings.register_profile("ci", _base, max_examples=25, deadline=None, print_blob=True)
settings.register_profile("dev", _base, deadline=None)
settings.load_profile(
    os.environ.get("HYPOTHESIS_PROFILE")
    or ("ci" if os.environ.get("CI", "").lower() == "true" else "dev")
)

from helpers.paths import SHARED_DATA

# the session fixture ``browser`` (headless Chromium) the browser tests share
pytest_plugins = ["helpers.chromium"]


@pytest.fixture(scope="session")
def shared_data() -> Path:
    """``../shared/data`` (third-party meshes, read-only); skips the test when absent."""
    if not SHARED_DATA.is_dir():
        pytest.skip(f"shared test data not found at {SHARED_DATA}")
    return SHARED_DATA


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--runslow", action="store_true", default=False, help="also run tests marked slow"
    )


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    skip_slow = pytest.mark.skip(reason="slow: run with --runslow")
    for item in items:
        if "slow" in item.keywords and not config.getoption("--runslow"):
            item.add_marker(skip_slow)


_SKIP_KINDS = (
    ("slow: run with --runslow", "slow (run with --runslow)"),
    ("shared test data not found", "no ../shared/data"),
    ("headless chromium", "no chromium"),
    ("could not import", "a missing optional package"),
)


def skip_summary(reasons: list[str]) -> str:
    """One line: how many tests were skipped and why, the commonest reason first."""
    counts: dict[str, int] = {}
    for reason in reasons:
        reason = reason.removeprefix("Skipped: ")
        kind = next((label for marker, label in _SKIP_KINDS if marker in reason), reason)
        counts[kind] = counts.get(kind, 0) + 1
    parts = [f"{count} {kind}" for kind, count in
             sorted(counts.items(), key=lambda item: (-item[1], item[0]))]
    return f"skipped {len(reasons)}: " + ", ".join(parts)


def pytest_terminal_summary(terminalreporter: Any) -> None:
    """After the run, one line that says what was skipped and why."""
    reports = terminalreporter.stats.get("skipped", [])
    reasons = []
    for report in reports:
        longrepr = getattr(report, "longrepr", None)
        reasons.append(str(longrepr[2]) if isinstance(longrepr, tuple) else str(longrepr))
    if reasons:
        terminalreporter.write_line(skip_summary(reasons))
