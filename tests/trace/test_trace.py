"""Traces: recording, JSON-Lines files, replay with digest checks, divergence, and
byte-identical files across processes with different hash seeds."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from geomexact import (
    FormatError,
    Mesh2,
    OverwriteError,
    Step,
    Trace,
    TraceError,
    first_divergence,
    mesh_from_triangles,
    read_trace,
    replay,
    trace_of,
    write_trace,
)
from geomexact.io.trace_file import parse_trace, trace_text
from geomexact.kernel.points import point2
from geomexact.mesh2d.ops import bisect_in, insert_in_edge_in, legalize_in
from geomexact.mesh2d.transient import Transient2
from geomexact.strategies import meshes_with_traces
from geomexact.trace.playback import replay_iter


def square() -> Mesh2:
    return mesh_from_triangles(
        [(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)], [(0, 1, 1), (1, 2, 1)]
    )


def recorded() -> tuple[Mesh2, Mesh2, Trace]:
    start = square()
    transient = Transient2(start)
    bisect_in(transient, 0, 2)
    insert_in_edge_in(transient, 0, 1, point2("0.1", 0))
    legalize_in(transient, 5)
    end = transient.seal()
    return start, end, trace_of(start, transient, {"method": "test", "k": 3})


def test_replay_reproduces_the_result() -> None:
    start, end, trace = recorded()
    assert replay(start, trace) == end
    assert replay(start, trace).digest == trace.final_digest


def test_replay_until_stops_after_k_steps() -> None:
    start, _, trace = recorded()
    assert replay(start, trace, until=0) == start
    assert replay(start, trace, until=1).vertex_count == 5
    with pytest.raises(TraceError, match="outside"):
        replay(start, trace, until=len(trace) + 1)


def test_replay_refuses_a_trace_of_another_mesh() -> None:
    _, end, trace = recorded()
    with pytest.raises(TraceError, match="not the trace's input"):
        replay(end, trace)


def test_replay_names_the_first_diverging_step() -> None:
    start, _, trace = recorded()
    forged = Trace(trace.input_digest, trace.steps, (trace.digests[0], 1, *trace.digests[2:]))
    with pytest.raises(TraceError, match="step 2"):
        replay(start, forged)


def test_replay_iter_yields_every_snapshot() -> None:
    start, end, trace = recorded()
    snapshots = list(replay_iter(start, trace))
    assert [m.digest for m in snapshots] == list(trace.digests)
    assert snapshots[-1] == end


def test_trace_file_round_trip(tmp_path: Path) -> None:
    _, _, trace = recorded()
    path = tmp_path / "run.trace.jsonl"
    write_trace(path, trace)
    assert read_trace(path) == trace
    with pytest.raises(OverwriteError):
        write_trace(path, trace)
    write_trace(path, trace, overwrite=True)


def test_trace_text_uses_p_over_q_for_rationals() -> None:
    _, _, trace = recorded()
    text = trace_text(trace)
    assert '"args":[0,1,"1/10","0/1"]' in text
    assert text.splitlines()[0].startswith('{"format":"geomexact-trace"')


@pytest.mark.parametrize(
    ("mutation", "message"),
    [
        (lambda lines: ["not json", *lines[1:]], ":1: not valid JSON"),
        (lambda lines: [lines[0].replace("geomexact-trace", "x"), *lines[1:]], "not a geomexact"),
        (lambda lines: lines[:-1], "truncated trace"),
        (lambda lines: [lines[0], lines[2], *lines[3:]], ":2: expected step number 1"),
        (lambda lines: [lines[0], lines[1].replace('"args":[0,2]', '"args":[0.5,2]'),
                        *lines[2:]], ":2: step argument 0.5"),
        (lambda lines: [lines[0], lines[1].replace('"digest":"', '"digest":"zz'), *lines[2:]],
         ":2: a digest must be"),
    ],
)
def test_bad_trace_files_name_the_line(mutation: object, message: str) -> None:
    _, _, trace = recorded()
    lines = trace_text(trace).splitlines()
    broken = "\n".join(mutation(lines)) + "\n"  # type: ignore[operator]
    with pytest.raises(FormatError, match=message):
        parse_trace(broken, "run.jsonl")


def test_first_divergence() -> None:
    start, _, trace = recorded()
    assert first_divergence(trace, trace) is None
    shorter = Trace(trace.input_digest, trace.steps[:1], trace.digests[:1])
    assert first_divergence(trace, shorter) == 1
    changed = Trace(trace.input_digest, (Step("bisect", (1, 2)), *trace.steps[1:]),
                    trace.digests)
    assert first_divergence(trace, changed) == 0
    other_input = Trace(0, trace.steps, trace.digests)
    assert first_divergence(trace, other_input) == 0


@given(meshes_with_traces(max_steps=20))
def test_replay_reproduces_every_digest(case: tuple[Mesh2, Mesh2, Trace]) -> None:
    start, end, trace = case
    assert parse_trace(trace_text(trace)) == trace
    assert replay(start, trace) == end


@given(meshes_with_traces(max_steps=10), st.integers(0, 10))
def test_replay_prefix_is_the_intermediate_mesh(
    case: tuple[Mesh2, Mesh2, Trace], k: int
) -> None:
    start, _, trace = case
    k = min(k, len(trace))
    expected = start
    for snapshot in list(replay_iter(start, trace))[:k]:
        expected = snapshot
    assert replay(start, trace, until=k) == expected


_WORKLOAD = r"""
import random, sys
from geomexact import mesh_from_triangles, trace_of
from geomexact.mesh2d.ops import bisect_in, insert_centroid_in, legalize_in, flip_in
from geomexact.errors import PreconditionError
from geomexact.io.trace_file import trace_text
from geomexact.mesh2d.transient import Transient2
n = 6
points = [(x, y) for y in range(n) for x in range(n)]
triangles = []
for y in range(n - 1):
    for x in range(n - 1):
        a, b, c, d = y * n + x, y * n + x + 1, (y + 1) * n + x + 1, (y + 1) * n + x
        triangles += [(a, b, c), (a, c, d)]
start = mesh_from_triangles(points, triangles)
t = Transient2(start)
rng = random.Random(7)
for _ in range(400):
    edges = sorted(t.iter_edges())
    u, v = rng.choice(edges)
    kind = rng.randrange(3)
    try:
        if kind == 0:
            legalize_in(t, bisect_in(t, u, v))
        elif kind == 1:
            legalize_in(t, insert_centroid_in(t, u, v))
        else:
            flip_in(t, u, v)
    except PreconditionError:
        pass
t.seal()
sys.stdout.write(trace_text(trace_of(start, t, {"seed": 7})))
"""


def test_trace_files_are_identical_across_hash_seeds() -> None:
    """The same run in two processes with different PYTHONHASHSEED writes byte-identical
    trace files."""
    outputs = []
    for seed in ("0", "4242"):
        environment = {**os.environ, "PYTHONHASHSEED": seed}
        result = subprocess.run(
            [sys.executable, "-c", _WORKLOAD],
            capture_output=True,
            env=environment,
            check=True,
        )
        outputs.append(result.stdout)
    assert outputs[0] == outputs[1]
    assert outputs[0].count(b"\n") > 100


def test_a_trace_rebuilds_from_its_own_fields() -> None:
    """``Trace(..., parameters=trace.parameters)`` and ``attrs.evolve`` keep the
    parameters (they are stored as sorted pairs)."""
    import attrs

    from geomexact.trace.record import Trace

    trace = Trace(1, [], [], {"b": 2, "a": "x"}, "0.1.0")
    again = Trace(trace.input_digest, trace.steps, trace.digests, trace.parameters,
                  trace.version)
    assert again == trace == attrs.evolve(trace)
    assert trace.parameter("a") == "x" and trace.parameters == (("a", "x"), ("b", 2))
