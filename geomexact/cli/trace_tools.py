"""``geomexact trace``: debugging with traces.

- ``trace show TRACE``: the header (input, version, parameters with the command line that
  recorded it), the number of steps and of each operation; with ``--step K`` or
  ``--steps A-B`` each step's arguments, digest and the cells it removed and added; which
  steps were replayed (their digests checked) and which not (``--check``: every one);
- ``trace diff INPUT A B``: the first step where two traces of the same input part, with
  a picture of both meshes after it (``--picture``);
- ``trace bisect INPUT TRACE --fails CHECK``: the first step after which a property
  fails, found by binary search (O(log n) checks), with the meshes before and after it
  (``-o DIR``).
"""

from __future__ import annotations

import argparse
import json
import math
import shlex
import sys
from collections import Counter
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from geomexact.cli.arguments import (
    Subcommands,
    add_check_flag,
    add_command,
    add_command_parser,
    add_input_argument,
    add_output_option,
    add_picture_option,
    add_reading_options,
    add_trace_argument,
    positive_int,
)
from geomexact.cli.errors import UsageProblem, cli_wording
from geomexact.cli.exit_codes import EXIT_FAILED, EXIT_OK
from geomexact.cli.loading import load
from geomexact.cli.replay import (
    is_mixed_trace,
    rebuilt_start,
    start_of,
    trace_dimension,
    wrong_input,
)
from geomexact.cli.reporting import print_json
from geomexact.cli.trace_checks import CHECKS_HELP, named_check
from geomexact.cli.writing import check_outputs, write
from geomexact.errors import FormatError, PreconditionError, TraceError
from geomexact.io.trace_file import (
    FORMAT_NAME,
    FORMAT_VERSION,
    HEADER_DIGEST,
    read_trace,
    read_trace_header,
)
from geomexact.kernel.digest import digest_text
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.trace.playback import first_divergence
from geomexact.trace.record import Trace
from geomexact.trace.step import Step
from geomexact.trace.stepper import Change, Stepper, first_failing_step

Mesh = Mesh2 | Mesh3 | MixedMesh3


# -----------------------------------------------------------------------------------------
# shared
# -----------------------------------------------------------------------------------------
def step_json(trace: Trace, k: int) -> dict[str, Any]:
    """Step k (1-based) of ``trace`` as JSON: ``step``, ``op``, ``args`` (vertex ids as
    integers, rationals as ``"p/q"``) and ``digest`` (after it)."""
    step = trace.steps[k - 1]
    return {"step": k, "op": step.op,
            "args": [a if isinstance(a, int) else f"{a.numerator}/{a.denominator}"
                     for a in step.args],
            "digest": digest_text(trace.digests[k - 1])}


def _step_text(step: Step) -> str:
    """``op a b p/q``: a step as it reads on a line."""
    return " ".join([step.op, *(str(a) if isinstance(a, int) else
                                f"{a.numerator}/{a.denominator}" for a in step.args)])


def _cells_word(mesh: Mesh) -> str:
    return ("tetrahedra" if isinstance(mesh, Mesh3) else "cells"
            if isinstance(mesh, MixedMesh3) else "triangles")


def _simplicial(mesh: Mesh, what: str) -> Mesh2 | Mesh3:
    """``mesh`` when it is a triangle or tetrahedral mesh; a :class:`UsageProblem` for a
    mixed-cell mesh, which ``what`` does not take yet."""
    if isinstance(mesh, MixedMesh3):
        raise UsageProblem(f"{what} takes triangle and tetrahedral meshes, not a mixed-cell "
                           "mesh (replay and trace show do)")
    return mesh


def _cells_text(cells: Sequence[tuple[int, ...]]) -> str:
    return " ".join("(" + ", ".join(str(v) for v in cell) + ")" for cell in cells) or "none"


def _diverged(trace_path: str, error: TraceError, as_json: bool,
              report: dict[str, Any]) -> int:
    """Report a step that does not replay as recorded (exit 1)."""
    message = f"{trace_path}: {cli_wording(str(error))}"
    print(f"geomexact: trace diverged: {message}", file=sys.stderr)
    if as_json:
        print_json({**report, "diverged": True, "error": message, "step": error.step})
    return EXIT_FAILED


def _given_start(input_path: str, format: str | None, verbose: bool, trace_path: str,
                 trace: Trace) -> Mesh:
    """The mesh INPUT gives for ``trace`` (a PSLG's vertices for a triangulation trace);
    a :class:`UsageProblem` when it is of the wrong kind or not the trace's input."""
    value = load(input_path, format, verbose).value
    start = start_of(input_path, value, trace_path, trace_dimension(trace),
                     is_mixed_trace(trace))
    if start.digest != trace.input_digest:
        raise UsageProblem(wrong_input(input_path, value, start, trace_path, trace))
    return start


def _json_value(value: Any) -> str:
    if isinstance(value, list) and all(isinstance(item, str) for item in value):
        return shlex.join(value)
    return value if isinstance(value, str) else json.dumps(value, sort_keys=True)


# -----------------------------------------------------------------------------------------
# trace show
# -----------------------------------------------------------------------------------------
def step_range(text: str) -> tuple[int, int]:
    """``A-B`` (1-based, inclusive, A <= B) as the pair (A, B)."""
    first, dash, last = text.partition("-")
    try:
        a, b = int(first), int(last) if dash else int(first)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a range A-B of step numbers"
                                         ) from None
    if a < 1 or b < a:
        raise argparse.ArgumentTypeError(f"{text!r}: need 1 <= A <= B")
    return a, b


def _selected(args: argparse.Namespace, total: int) -> range | None:
    if args.step is not None:
        first, last, option = args.step, args.step, f"--step {args.step}"
    elif args.steps is not None:
        (first, last), option = args.steps, f"--steps {args.steps[0]}-{args.steps[1]}"
    else:
        return None
    if last > total:
        raise UsageProblem(f"{option}: {args.trace} has {total} step"
                           f"{'s' if total != 1 else ''}"
                           f"{f' (1..{total})' if total else ''}")
    return range(first, last + 1)


def _show_start(args: argparse.Namespace, trace: Trace) -> tuple[Mesh | None, str, str]:
    """The trace's input mesh for ``show``: (mesh or None, where it came from — ``input``,
    ``rebuilt`` or ``beside`` — and, without one, why)."""
    if args.input is not None:
        return _given_start(args.input, args.format, args.verbose, args.trace, trace), \
            "input", ""
    if trace.parameter("algorithm") == "cuboid":
        try:
            rebuilt = rebuilt_start(trace)
        except PreconditionError as error:
            return None, "", f"its start cannot be rebuilt ({error.problem}); give --input"
        if rebuilt.digest == trace.input_digest:
            return rebuilt, "rebuilt", ""
        return None, "", ("the start rebuilt from its parameters is not its input; give "
                          "--input")
    if not trace.input_name:
        return None, "", "the trace names no input file; give --input INPUT"
    beside = Path(args.trace).parent / trace.input_name
    if not beside.is_file():
        return None, "", f"its input {trace.input_name} is not beside it; give --input INPUT"
    try:
        value = load(str(beside), None, False).value
        start = start_of(str(beside), value, args.trace, trace_dimension(trace),
                         is_mixed_trace(trace))
    except (FormatError, UsageProblem) as error:
        return None, "", f"{beside} does not read as its input ({error}); give --input INPUT"
    if start.digest != trace.input_digest:
        return None, "", (f"{beside} has digest {start.digest_text}, not the trace's input "
                          f"{digest_text(trace.input_digest)}; give --input INPUT")
    return start, "beside", ""


def command_show(args: argparse.Namespace) -> int:
    """Print a trace's header and operation counts, and the chosen steps; say which steps
    were replayed (their digests checked) and which were not (``--check``: all are)."""
    trace = read_trace(args.trace)
    total = len(trace)
    chosen = _selected(args, total)
    operations = dict(sorted(Counter(step.op for step in trace.steps).items()))
    report: dict[str, Any] = {
        "trace": args.trace,
        "format": FORMAT_NAME,
        "format_version": FORMAT_VERSION,
        "geomexact": trace.version,
        "input_name": trace.input_name or None,
        "input_digest": digest_text(trace.input_digest),
        "final_digest": digest_text(trace.final_digest),
        "dimension": trace_dimension(trace),
        "parameters": dict(trace.parameters),
        "steps": total,
        "operations": operations,
        "header_checked": HEADER_DIGEST in read_trace_header(args.trace),
    }
    shown: list[dict[str, Any]] = []
    note = ""
    stepper = None
    looked = chosen is not None or args.check  # for the input: cells and replays need it
    if looked:
        start, source, note = _show_start(args, trace)
        if args.check and start is None:
            raise UsageProblem(f"--check replays {args.trace} on its input: {note}")
        stepper = None if start is None else Stepper(start, trace)
        if chosen is not None:
            report["cells_from"] = source or None
            report["cells"] = None if start is None else _cells_word(start)
            report["cells_note"] = note or None
    checked = 0  # steps 1..checked replayed, each digest as recorded
    try:
        if args.check and stepper is not None:
            stepper.goto(total)
            checked = total
        for k in chosen or ():
            entry = step_json(trace, k)
            if stepper is not None:
                stepper.goto(k)
                checked = max(checked, k)
                change = stepper.changed
                entry["removed"] = [list(cell) for cell in change.removed]
                entry["added"] = [list(cell) for cell in change.added]
            shown.append(entry)
    except TraceError as error:
        return _diverged(args.trace, error, args.json, report)
    if chosen is not None:
        report["shown"] = shown
    report["checked_steps"] = checked
    report["unchecked_steps"] = total - checked
    report["check_note"] = _check_note(args, total, checked,
                                       (stepper is not None) if looked else None)
    if args.json:
        print_json(report)
        return EXIT_OK
    _print_show(args.trace, trace, report, chosen, note)
    return EXIT_OK


def _check_note(args: argparse.Namespace, total: int, checked: int, found: bool | None
                ) -> str | None:
    """What was not checked, and the command that checks it (None: every step was);
    ``found``: whether the trace's input was found (None: not looked for)."""
    if checked == total:
        return None
    unchecked = f"step {total}" if checked == total - 1 else f"steps {checked + 1}-{total}"
    given = f" --input {shlex.quote(args.input)}" if args.input else ""
    if found is False:
        given = " --input INPUT"
    return (f"{unchecked} not replayed, their digests not checked: geomexact trace show "
            f"{shlex.quote(args.trace)} --check{given} (or geomexact replay) checks them")


def _print_show(path: str, trace: Trace, report: dict[str, Any], chosen: range | None,
                note: str) -> None:
    print(f"{path}: {FORMAT_NAME} format {FORMAT_VERSION}, recorded by geomexact "
          f"{trace.version or '(unknown version)'}")
    name = f"{trace.input_name}, " if trace.input_name else ""
    rows = [("input", f"{name}digest {report['input_digest']}"),
            ("final digest", report["final_digest"]),
            ("dimension", f"{report['dimension']}D" if report["dimension"] else "unknown"),
            ("header", "checked against its header_digest" if report["header_checked"] else
             "not covered by a digest (a trace written before header_digest)"),
            ("steps", str(report["steps"])),
            ("operations", ", ".join(f"{op} {count}" for op, count in
                                     report["operations"].items()) or "none")]
    width = max(len(key) for key, _ in rows)
    for key, value in rows:
        print(f"  {key:<{width}}  {value}")
    if trace.parameters:
        print("  parameters")
        inner = max(len(key) for key, _ in trace.parameters)
        for key, value in trace.parameters:
            print(f"    {key:<{inner}}  {_json_value(value)}")
    if chosen is not None:
        _print_steps(trace, report, note)
    print(_checked_line(report["checked_steps"], report["steps"], report["check_note"]))


def _checked_line(checked: int, total: int, note: str | None) -> str:
    if total == 0:
        return "checked: the trace has no steps"
    if note is None:
        return f"checked: all {total} steps replay as recorded" if total > 1 else \
            "checked: its one step replays as recorded"
    if checked == 0:
        return f"not checked: {note}"
    done = "step 1 replays" if checked == 1 else f"steps 1-{checked} replay"
    return f"checked: {done} as recorded; {note}"


def _print_steps(trace: Trace, report: dict[str, Any], note: str) -> None:
    if note:
        print(f"cells not shown: {note}")
    for entry in report["shown"]:
        step = trace.steps[entry["step"] - 1]
        print(f"step {entry['step']}: {_step_text(step)}")
        print(f"  digest   {entry['digest']}")
        if "removed" in entry:
            word = report["cells"]
            removed = [tuple(c) for c in entry["removed"]]
            added = [tuple(c) for c in entry["added"]]
            print(f"  removed  {len(removed)} {word}: {_cells_text(removed)}")
            print(f"  added    {len(added)} {word}: {_cells_text(added)}")


# -----------------------------------------------------------------------------------------
# trace diff
# -----------------------------------------------------------------------------------------
def _picture_check(path: str | None, force: bool) -> None:
    """Refuse, before any work, a picture that cannot be written."""
    if path is None:
        return
    if Path(path).suffix.lower() not in (".png", ".svg", ".pdf"):
        raise UsageProblem(f"{path}: a picture must be .png, .svg or .pdf")
    check_outputs([("--picture", path, "file")], Mesh2, force=force)


def command_diff(args: argparse.Namespace) -> int:
    """Find the first step where two traces of one input part."""
    a, b = read_trace(args.a), read_trace(args.b)
    if a.input_digest != b.input_digest:
        raise UsageProblem(
            f"{args.a} and {args.b} were recorded on different inputs "
            f"({_recorded_on(a)} and {_recorded_on(b)}): only traces of the same input "
            "compare step by step")
    _picture_check(args.picture, args.force)
    start = _given_start(args.input, args.format, args.verbose, args.a, a)
    index = first_divergence(a, b)
    report: dict[str, Any] = {
        "input": args.input, "a": args.a, "b": args.b,
        "input_digest": digest_text(a.input_digest),
        "steps_a": len(a), "steps_b": len(b),
        "identical": index is None,
        "first_difference": None, "common_steps": len(a) if index is None else index,
        "prefix": False, "longer": None,
        "step_a": None, "step_b": None, "digest_a": None, "digest_b": None,
        "cells": _cells_word(start), "only_in_a": None, "only_in_b": None,
        "picture": None, "picture_highlights": None,
    }
    if index is None:
        if args.json:
            print_json(report)
        else:
            print(f"{args.a} and {args.b} are identical: {len(a)} steps on input digest "
                  f"{report['input_digest']}, final digest {digest_text(a.final_digest)}")
        return EXIT_OK
    k = index + 1
    report["first_difference"] = k
    if index == min(len(a), len(b)):
        longer, shorter = ("a", "b") if len(a) > len(b) else ("b", "a")
        report.update(prefix=True, longer=longer)
        long_trace = a if longer == "a" else b
        report[f"step_{longer}"] = step_json(long_trace, k)
        report[f"digest_{longer}"] = digest_text(long_trace.digests[index])
        if args.json:
            print_json(report)
        else:
            paths = {"a": args.a, "b": args.b}
            print(f"{paths[shorter]} is a prefix of {paths[longer]}: the first {index} steps "
                  f"agree, then {paths[longer]} is longer ({len(long_trace)} steps, "
                  f"{len(long_trace) - index} more, from step {k}: "
                  f"{_step_text(long_trace.steps[index])})")
            if args.picture:
                print("no picture: the shorter trace has no step to compare")
        return EXIT_FAILED
    try:
        after_a = Stepper(start, a).goto(k)
    except TraceError as error:
        return _diverged(args.a, error, args.json, report)
    try:
        after_b = Stepper(start, b).goto(k)
    except TraceError as error:
        return _diverged(args.b, error, args.json, report)
    cells_a, cells_b = set(after_a.cells()), set(after_b.cells())
    only_a, only_b = sorted(cells_a - cells_b), sorted(cells_b - cells_a)
    report.update(step_a=step_json(a, k), step_b=step_json(b, k),
                  digest_a=digest_text(a.digests[index]),
                  digest_b=digest_text(b.digests[index]),
                  only_in_a=[list(c) for c in only_a], only_in_b=[list(c) for c in only_b])
    note = ""
    if args.picture:
        from geomexact.viz.trace_pictures import highlights_cells, plot_pair

        plot_pair(_simplicial(after_a, "trace diff --picture"),
                  _simplicial(after_b, "trace diff --picture"), args.picture,
                  overwrite=args.force,
                  titles=(f"{Path(args.a).name}: {_step_text(a.steps[index])}",
                          f"{Path(args.b).name}: {_step_text(b.steps[index])}"),
                  highlights=(only_a, only_b),
                  title=f"after step {k}, the first that differs")
        highlighted = highlights_cells(_simplicial(after_a, "trace diff --picture"))
        report.update(picture=args.picture, picture_highlights=highlighted)
        note = (f"wrote {args.picture} (both meshes after step {k}; the cells that differ "
                "filled in orange)" if highlighted else
                f"wrote {args.picture} (both meshes after step {k} side by side; 3D pictures "
                "cannot highlight the cells that differ)")
    if args.json:
        print_json(report)
        return EXIT_FAILED
    word = _cells_word(start)
    print(f"{args.a} and {args.b} agree on {index} steps and differ at step {k}:")
    print(f"  {args.a}: {_step_text(a.steps[index])}  digest {report['digest_a']}")
    print(f"  {args.b}: {_step_text(b.steps[index])}  digest {report['digest_b']}")
    print(f"  after it, {len(only_a)} {word} only in {args.a}: {_cells_text(only_a)}")
    print(f"  after it, {len(only_b)} {word} only in {args.b}: {_cells_text(only_b)}")
    if note:
        print(note)
    return EXIT_FAILED


def _recorded_on(trace: Trace) -> str:
    name = f"{trace.input_name}, " if trace.input_name else ""
    return f"{name}digest {digest_text(trace.input_digest)}"


# -----------------------------------------------------------------------------------------
# trace bisect
# -----------------------------------------------------------------------------------------
def check_bound(steps: int) -> int:
    """The most checks :func:`~geomexact.trace.stepper.first_failing_step` runs on a
    trace of ``steps`` steps: ⌈log₂ n⌉ + 2."""
    return math.ceil(math.log2(steps)) + 2 if steps > 1 else 2


def _bisect_start(args: argparse.Namespace, trace: Trace) -> Mesh:
    if args.input is not None:
        return _given_start(args.input, args.format, args.verbose, args.trace, trace)
    try:
        rebuilt = rebuilt_start(trace)
    except PreconditionError as error:
        raise UsageProblem(
            f"{args.trace}: give the INPUT mesh the trace was recorded on (geomexact trace "
            f"bisect INPUT {args.trace} --fails CHECK); {error.problem}") from error
    if rebuilt.digest != trace.input_digest:
        raise UsageProblem(wrong_input(None, rebuilt, rebuilt, args.trace, trace))
    return rebuilt


def command_bisect(args: argparse.Namespace) -> int:
    """Find the first step after which CHECK fails, by binary search."""
    trace = read_trace(args.trace)
    start = _bisect_start(args, trace)
    check = named_check(args.fails, _simplicial(start, "trace bisect"))
    total = len(trace)
    report: dict[str, Any] = {
        "input": args.input, "trace": args.trace, "check": check.name,
        "dimension": 2 if isinstance(start, Mesh2) else 3, "steps": total,
        "failing_step": None, "failed_at_start": False, "holds": False,
        "checks": 0, "check_bound": check_bound(total),
        "step": None, "cells": _cells_word(start), "removed": None, "added": None,
        "written": [],
    }
    stepper = Stepper(start, trace)
    try:
        found = first_failing_step(stepper, check.holds)
    except TraceError as error:
        return _diverged(args.trace, error, args.json, report)
    report.update(failing_step=found.step, failed_at_start=found.failed_at_start,
                  holds=found.step is None and not found.failed_at_start,
                  checks=found.checks)
    if found.step is None:
        if args.json:
            print_json(report)
        elif found.failed_at_start:
            print(f"{check.name} already fails on the input (before step 1; "
                  f"{found.checks} check)")
        else:
            print(f"{check.name} holds after every step ({total} steps; {found.checks} "
                  "checks)")
        return EXIT_FAILED if found.failed_at_start else EXIT_OK
    k = found.step
    before, after = stepper.goto(k - 1), stepper.goto(k)
    change: Change = stepper.changed
    report.update(step=step_json(trace, k),
                  removed=[list(c) for c in change.removed],
                  added=[list(c) for c in change.added])
    if args.output:
        report["written"] = [str(p) for p in _write_bisection(args, before, after, change, k,
                                                              trace.steps[k - 1])]
    if args.json:
        print_json(report)
        return EXIT_FAILED
    word = report["cells"]
    print(f"{check.name} holds after step {k - 1} and fails after step {k} of {total} "
          f"({found.checks} checks, at most {report['check_bound']})")
    print(f"  step {k}: {_step_text(trace.steps[k - 1])}  digest {report['step']['digest']}")
    print(f"  removed  {len(change.removed)} {word}: {_cells_text(change.removed)}")
    print(f"  added    {len(change.added)} {word}: {_cells_text(change.added)}")
    for path in report["written"]:
        print(f"wrote {path}")
    return EXIT_FAILED


def _write_bisection(args: argparse.Namespace, before: Mesh, after: Mesh, change: Change,
                     k: int, step: Step) -> list[Path]:
    """Write the meshes before and after step k (exact Triangle/TetGen .ele) and a picture
    of both into ``args.output``; nothing is written when one of them exists (no
    ``--force``)."""
    from geomexact.viz.trace_pictures import plot_pair  # matplotlib checked before writing

    directory = Path(args.output)
    if directory.exists() and not directory.is_dir():
        raise UsageProblem(f"{directory} (-o): exists and is not a directory")
    mesh_before = directory / f"before-step-{k}.ele"
    mesh_after = directory / f"after-step-{k}.ele"
    picture = directory / f"step-{k}.png"
    if directory.is_dir():
        check_outputs([("-o", str(mesh_before), "triangle"), ("-o", str(mesh_after), "triangle"),
                       ("-o", str(picture), "file")], type(before), force=args.force)
    directory.mkdir(parents=True, exist_ok=True)
    written = write(mesh_before, before, "triangle", overwrite=args.force, numbers="exact")
    written += write(mesh_after, after, "triangle", overwrite=args.force, numbers="exact")
    plot_pair(_simplicial(before, "trace bisect"), _simplicial(after, "trace bisect"), picture,
              overwrite=args.force,
              titles=(f"before step {k}", f"after step {k}: {_step_text(step)}"),
              highlights=(change.removed, change.added),
              title=f"{args.fails} fails after step {k}")
    return [*written, picture]


# -----------------------------------------------------------------------------------------
# the parser
# -----------------------------------------------------------------------------------------
def add_parser(commands: Subcommands) -> None:
    """Add the ``trace`` command and its subcommands ``show``, ``diff`` and ``bisect``."""
    trace_ = add_command_parser(commands, "trace")
    tools: Subcommands = trace_.add_subparsers(dest="trace_command", metavar="SUBCOMMAND",
                                               required=True)

    show = add_command(tools, "trace show", command_show)
    add_trace_argument(show)
    show.add_argument("--input", metavar="INPUT",
                      help="the mesh the trace was recorded on (for the cells each step "
                      "removed and added; default: a cuboid trace's rebuilt start, else "
                      "the file the trace names, beside it)")
    chosen = show.add_mutually_exclusive_group()
    chosen.add_argument("--step", type=positive_int, metavar="K", help="show step K (1-based)")
    chosen.add_argument("--steps", type=step_range, metavar="A-B",
                        help="show steps A to B (1-based, inclusive)")
    add_check_flag(show, "replay every step on the trace's input, checking its digest (exit "
                   "1 at the first that differs); otherwise only the steps up to the last "
                   "one shown are replayed")
    add_reading_options(show)

    diff = add_command(tools, "trace diff", command_diff)
    add_input_argument(diff, "the mesh both traces start from")
    diff.add_argument("a", metavar="A", help="first trace file")
    diff.add_argument("b", metavar="B", help="second trace file")
    add_picture_option(diff, "draw both meshes after the differing step (.png, .svg, .pdf)",
                       metavar="OUT")
    add_reading_options(diff, force="existing files")

    bisect = add_command(tools, "trace bisect", command_bisect)
    add_input_argument(bisect, "the mesh the trace was recorded on; may be left out for a "
                       "cuboid trace", optional=True)
    add_trace_argument(bisect)
    bisect.add_argument("--fails", required=True, metavar="CHECK",
                        help=f"the property that fails: {CHECKS_HELP}")
    add_output_option(bisect, "write the meshes before and after the failing step "
                      "(before-step-K.ele, after-step-K.ele) and a picture (step-K.png)",
                      metavar="DIR")
    add_reading_options(bisect, force="existing files")
