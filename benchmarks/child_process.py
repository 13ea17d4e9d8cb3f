"""Measuring a benchmark's runs in child processes, shared by the benchmark scripts: each
run in its own process (its own peak memory: ``os.wait4``'s rusage), its JSON report read
back, the best of several runs kept."""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import tempfile
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

__all__ = ["ROOT", "best_of", "child", "clock", "installed", "rate"]

ROOT = Path(__file__).resolve().parents[1]
"""The repository's root: the children import geomexact from here first."""


def clock() -> tuple[float, float]:
    return time.perf_counter(), time.process_time()


def child(command: list[str], timeout: float | None) -> dict[str, Any]:
    """Run ``command``; its wall time (launch to exit), CPU time and peak memory from its
    own rusage (``os.wait4``), its stdout as JSON (the whole output, or its last line)."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])]))
    expired: list[bool] = []

    def expire(process: subprocess.Popen[str]) -> None:
        expired.append(True)
        process.kill()

    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        started = time.perf_counter()
        process = subprocess.Popen(command, stdout=out, stderr=err, text=True, env=env)
        timer = threading.Timer(timeout, expire, (process,)) if timeout else None
        if timer is not None:
            timer.start()
        _, status, usage = os.wait4(process.pid, 0)
        wall = time.perf_counter() - started
        if timer is not None:
            timer.cancel()
        process.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        stdout, stderr = out.read(), err.read()
    if expired:
        return {"status": f"did not finish in {timeout:.0f} s"}
    if process.returncode != 0:
        last = (stderr.strip().splitlines() or stdout.strip().splitlines() or ["?"])[-1]
        return {"status": f"failed, exit {process.returncode} ({last[:160]})"}
    report: dict[str, Any] = {"status": "ok"}
    try:
        report.update(json.loads(stdout))
    except json.JSONDecodeError:
        lines = stdout.strip().splitlines() or ["{}"]
        try:
            report.update(json.loads(lines[-1]))
        except json.JSONDecodeError:
            return {"status": f"no JSON report ({lines[-1][:80]})"}
    report["process_seconds"] = wall
    report["process_cpu_seconds"] = usage.ru_utime + usage.ru_stime
    report["process_max_rss_mb"] = usage.ru_maxrss / 1024
    return report


def best_of(repeat: int, run: Callable[[], dict[str, Any]]) -> dict[str, Any]:
    best: dict[str, Any] | None = None
    for _ in range(repeat):
        report = run()
        if report.get("status") != "ok":
            return report
        if best is None or report["process_seconds"] < best["process_seconds"]:
            best = report
    assert best is not None
    return best


def installed(module: str) -> bool:

    return importlib.util.find_spec(module) is not None


def rate(tetrahedra: int, seconds: float) -> float:
    return tetrahedra / seconds if seconds > 0 else float("inf")
