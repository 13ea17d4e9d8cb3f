"""The README's Python example, and then its shell example, run as written."""

from __future__ import annotations

import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[2] / "README.md"


def python_blocks(text: str) -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.MULTILINE | re.DOTALL)


def test_readme_example_runs(capsys: pytest.CaptureFixture[str], tmp_path: Path,
                             monkeypatch: pytest.MonkeyPatch) -> None:
    """Every ```python block of README.md executes without error (in a fresh folder: it
    saves the files of the shell example)."""
    monkeypatch.chdir(tmp_path)
    blocks = python_blocks(README.read_text(encoding="utf-8"))
    assert blocks, "README.md has no python example"
    for block in blocks:
        exec(compile(block, str(README), "exec"), {"__name__": "readme_example"})
    assert "3 steps, 6 triangles" in capsys.readouterr().out


def test_readme_shell_example_runs_after_the_python_one(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
        capsys: pytest.CaptureFixture[str]) -> None:
    """Issue 26, item 7: the README's shell example runs as written, command by command,
    on the files its Python example saved (each exits 0; the replayed mesh checks)."""
    monkeypatch.chdir(tmp_path)
    text = README.read_text(encoding="utf-8")
    for block in python_blocks(text):
        exec(compile(block, str(README), "exec"), {"__name__": "readme_example"})
    capsys.readouterr()
    shell = [block for block in re.findall(r"^```sh\n(.*?)^```", text,
                                           flags=re.MULTILINE | re.DOTALL)
             if "geomexact replay" in block]
    assert len(shell) == 1
    lines = [line for line in shell[0].splitlines() if line.strip()]
    assert lines and all(line.startswith("geomexact ") for line in lines)
    for line in lines:
        words = shlex.split(line)
        done = subprocess.run([sys.executable, "-m", "geomexact", *words[1:]],
                              cwd=tmp_path, capture_output=True, text=True, timeout=120,
                              check=False)
        assert done.returncode == 0, (line, done.stderr)
    assert (tmp_path / "result.off").exists()


def test_readme_quick_start_has_exactly_two_commands() -> None:
    """The Quick start section shows exactly the two set-up commands."""
    text = README.read_text(encoding="utf-8")
    section = text.split("## Quick start", 1)[1].split("\n## ", 1)[0]
    (block,) = re.findall(r"```sh\n(.*?)```", section, flags=re.DOTALL)
    assert block.split("\n")[:-1] == ["scripts/main-job", "scripts/test"]
