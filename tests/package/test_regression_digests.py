"""Golden regression cases: real inputs run through the public API give exactly the
recorded step counts, final digests and trace files (``tests/data/regression``).  The
values were made by ``make_digests.py`` on the code before the re-layout and checked
identical after it; a change of any step, tie rule or file byte shows here.  Cases on
``../shared/data`` inputs skip where it is absent; Lake Superior ships in the package."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path
from typing import Any

import pytest

from geomexact import io, read_trace, replay, write_trace

HERE = Path(__file__).resolve().parents[1] / "data" / "regression"
_spec = importlib.util.spec_from_file_location("make_digests", HERE / "make_digests.py")
assert _spec is not None and _spec.loader is not None
make_digests: Any = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(make_digests)

GOLDEN: dict[str, Any] = json.loads((HERE / "digests.json").read_text())
CASES = {name: (spec, kind) for name, spec, kind in make_digests.CASES}


def test_every_case_has_a_golden_result() -> None:
    assert set(CASES) <= set(GOLDEN), sorted(set(CASES) - set(GOLDEN))


@pytest.mark.parametrize("name", sorted(CASES))
def test_case_gives_its_golden_result(name: str, tmp_path: Path) -> None:
    spec, kind = CASES[name]
    path = make_digests.source(spec)
    if not path.exists():
        pytest.skip(f"{path} is absent (../shared/data not here)")
    assert make_digests.case_result(spec, kind) == GOLDEN[name]


@pytest.mark.parametrize("name", sorted(n for n, (s, _) in CASES.items() if "package:" in s))
def test_case_trace_replays_from_its_file(name: str, tmp_path: Path) -> None:
    """The trace written to disk and read back replays to the golden final digest."""
    spec, kind = CASES[name]
    value = io.read(make_digests.source(spec))
    start, _, trace = make_digests.run(value, kind)
    write_trace(tmp_path / "run.trace.jsonl", trace)
    again = read_trace(tmp_path / "run.trace.jsonl")
    assert again == trace
    assert f"{replay(start, again).digest:032x}" == GOLDEN[name]["final_digest"]


def test_demo_writes_its_golden_files() -> None:
    assert make_digests.demo_result() == GOLDEN["demo"]["files"]
