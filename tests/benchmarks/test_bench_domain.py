"""``benchmarks/bench_domain.py`` (issue 24): its ``--help``, its ``--quick`` smoke run
(spot at level 3, geomexact only: no peers needed), and its "skipped" report when the
surfaces' directory is absent.  No timing is judged here."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "benchmarks" / "bench_domain.py"
SURFACES = ROOT.parent / "shared" / "data" / "surfaces"


def bench(*arguments: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, str(SCRIPT), *arguments], cwd=ROOT,
                          capture_output=True, text=True, timeout=300, check=False)


def test_help() -> None:
    done = bench("--help")
    assert done.returncode == 0, done.stderr
    for option in ("--quick", "--levels", "--peers", "--json", "--data"):
        assert option in done.stdout


def test_skipped_without_the_surfaces(tmp_path: Path) -> None:
    done = bench("--quick", "--json", "--data", str(tmp_path / "absent"))
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    assert report["status"].startswith("skipped") and report["runs"] == []


@pytest.mark.skipif(not (SURFACES / "spot.obj").is_file(),
                    reason="../shared/data/surfaces is absent")
def test_quick_run() -> None:
    done = bench("--quick", "--json")
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    assert report["status"] == "ok" and report["pass"] is True
    runs = {run["program"]: run for run in report["runs"]}
    assert set(runs) == {"geomexact library", "geomexact command"}
    command, library = runs["geomexact command"], runs["geomexact library"]
    assert command["status"] == library["status"] == "ok"
    assert command["level"] == 3 and command["tetrahedra"] > 0
    assert command["valid"] is True and command["boundary_on_surface"] is True
    assert library["digest"] == command["digest"]
    assert 0 < command["volume_error"] < 1 and 0 < library["min_dihedral"] < 90
    assert library["process_max_rss_mb"] > 0
