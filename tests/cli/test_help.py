"""Help that teaches (issue 26, item 7): every command's ``--help`` ends with two or three
examples that parse, the exit codes are listed once (top level, ``geomexact help
exit-codes``), ``geomexact help TOPIC`` is the documentation a pip user has, and a command
given no ``-o`` says its result was not written and which ``-o`` would write it."""

from __future__ import annotations

import argparse
import shlex
from pathlib import Path

import pytest

from geomexact.cli import main
from geomexact.cli.command_table import COMMAND_TABLE
from geomexact.cli.exit_codes import EXIT_CODES_HELP
from geomexact.cli.help import TOPICS, help_text
from geomexact.cli.parser import build_parser
from geomexact.cli.writing import numbered_output

SQUARE = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"


def _subparsers(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


def _every_command() -> list[tuple[str, argparse.ArgumentParser]]:
    found = []
    for name, sub in _subparsers(build_parser()).items():
        found.append((name, sub))
        found.extend((f"{name} {inner}", parser) for inner, parser in _subparsers(sub).items())
    return found


def _examples(parser: argparse.ArgumentParser) -> list[str]:
    text = parser.format_help()
    assert "\nexamples:\n" in text, parser.prog
    block = text.split("\nexamples:\n", 1)[1].split("\n\n", 1)[0]
    return [line.strip() for line in block.splitlines()]


def test_every_help_ends_with_examples_and_no_exit_code_table() -> None:
    commands = _every_command()
    assert {spec.name for spec in COMMAND_TABLE} <= {name for name, _ in commands}
    for name, parser in commands:
        examples = _examples(parser)
        assert 2 <= len(examples) <= 3, (name, examples)
        assert all(example.startswith(f"geomexact {name.split()[0]}") for example in examples)
        text = parser.format_help()
        if name != "help":
            assert text.rstrip().endswith("exit codes: geomexact help exit-codes"), name
        assert "0  success" not in text, name


def test_every_example_parses() -> None:
    """Each example is a valid command line (parsed by the real parser; files are not
    opened at parse time)."""
    parser = build_parser()
    for name, sub in _every_command():
        for example in _examples(sub):
            words = shlex.split(example)[1:]
            try:
                parser.parse_args(words)
            except SystemExit as error:  # pragma: no cover - a bad example
                pytest.fail(f"{name}: {example!r} does not parse ({error})")


def test_the_top_level_help_lists_exit_codes_once_and_points_to_help(
        capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    assert out.count("0  success") == 1 and EXIT_CODES_HELP in out
    assert "geomexact help TOPIC" in out and "docs/cli.md" not in out
    assert "examples:" in out


@pytest.mark.parametrize("topic", [None, *(name for name, _ in TOPICS)])
def test_topics(topic: str | None, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["help", *([topic] if topic else [])]) == 0
    out = capsys.readouterr().out
    assert out == help_text(topic)
    if topic == "formats":
        from geomexact import io

        assert all(f"  {name}:" in out for name in io.FORMATS)
    if topic == "exit-codes":
        assert out == EXIT_CODES_HELP
    if topic == "triangle":
        assert "-q  --min-angle" in out
    if topic is None:
        assert all(f"  {spec.name} " in out for spec in COMMAND_TABLE)


def test_help_of_a_command_is_its_help(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["help", "refine"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("usage: geomexact refine") and "examples:" in out


def test_an_unknown_topic_names_the_closest(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["help", "refin"]) == 2
    err = capsys.readouterr().err
    assert "no help topic 'refin'" in err and "did you mean 'refine'" in err


@pytest.mark.parametrize(("path", "expected"), [
    ("pk.off", "pk.1.off"), ("superior.1.ele", "superior.2.ele"),
    ("superior.poly", "superior.1.ele"), ("dir/x.9.off", "x.10.off"),
    ("points.node", "points.1.ele"), ("a.b.off", "a.b.1.off"),
])
def test_numbered_output(path: str, expected: str) -> None:
    assert numbered_output(path) == expected


@pytest.mark.parametrize("command", [["refine", "square.off", "--max-area", "0.1"],
                                     ["triangulate", "square.off"],
                                     ["polylla", "square.off"]])
def test_no_output_is_said(command: list[str], tmp_path: Path,
                           monkeypatch: pytest.MonkeyPatch,
                           capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "square.off").write_text(SQUARE)
    assert main(command) == 0
    err = capsys.readouterr().err
    assert "no -o given" in err and "-o square.1.off" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["square.off"]
