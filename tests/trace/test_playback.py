"""Replay is dimension-free (``geomexact.trace.protocols``, ``geomexact.trace.playback``):
a tiny counter "mesh" whose steps are ``add(k)`` and whose digest is its value satisfies
the protocols, and ``replay``, ``replay_iter``, ``first_divergence`` and every
``TraceError`` work with it exactly as with ``Mesh2``."""

from __future__ import annotations

import attrs
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact.errors import TraceError
from geomexact.trace import protocols
from geomexact.trace.playback import check_start, first_divergence, replay, replay_iter
from geomexact.trace.record import Trace, trace_of
from geomexact.trace.step import Step

FEW = settings(max_examples=min(settings().max_examples, 60))
OPENED: list[CounterTransient] = []  # every transient opened, to count them


@attrs.frozen
class Counter:
    """An immutable "mesh": one non-negative integer, which is also its digest."""

    value: int

    @property
    def digest(self) -> int:
        return self.value

    def transient(self, *, batch: bool = False) -> CounterTransient:
        transient = CounterTransient(self.value)
        OPENED.append(transient)
        return transient


class CounterTransient:
    """Its batch builder: applies ``add(k)`` (refusing unknown steps and negative totals
    with ValueError), records each step with the value after it, seals once."""

    def __init__(self, value: int) -> None:
        self.value = value
        self.sealed = False
        self.steps: list[Step] = []
        self.step_digests: list[int] = []

    @property
    def digest(self) -> int:
        return self.value

    def apply(self, step: Step, /) -> None:
        if self.sealed:
            raise RuntimeError("sealed")
        if step.op != "add" or len(step.args) != 1:
            raise ValueError(f"unknown step {step}")
        (k,) = step.args
        if self.value + k < 0:
            raise ValueError(f"add({k}) would make {self.value} negative")
        self.value += int(k)
        self.steps.append(step)
        self.step_digests.append(self.value)

    def seal(self) -> Counter:
        if self.sealed:
            raise RuntimeError("sealed twice")
        self.sealed = True
        return Counter(self.value)


def run(start: int, ks: list[int]) -> tuple[Counter, Counter, Trace]:
    """Record ``add(k)`` for each k from ``start``: (start, end, trace)."""
    mesh = Counter(start)
    transient = mesh.transient()
    for k in ks:
        transient.apply(Step("add", (k,)))
    return mesh, transient.seal(), trace_of(mesh, transient, {"fake": True})


@pytest.fixture(autouse=True)
def forget_opened() -> None:
    OPENED.clear()


additions = st.lists(st.integers(0, 50), max_size=15)


# -- the protocols ----------------------------------------------------------------------------
def protocol_members(protocol: type) -> set[str]:
    return {name for name in vars(protocol) if not name.startswith("_")}


def test_the_fake_offers_every_member_of_the_protocols() -> None:
    """The counter pair has every public member that Snapshot and Transient declare (so it
    is a fair stand-in for a mesh type)."""
    assert protocol_members(protocols.Snapshot) == {"digest", "transient"}
    assert protocol_members(protocols.Transient) == {
        "digest", "steps", "step_digests", "apply", "seal"}
    snapshot: protocols.Snapshot = Counter(0)  # and mypy checks the types against them
    transient: protocols.Transient = snapshot.transient()
    for name in protocol_members(protocols.Transient):
        assert hasattr(transient, name)
    for name in protocol_members(protocols.Snapshot):
        assert hasattr(snapshot, name)


def test_trace_of_records_the_fake_run() -> None:
    """trace_of takes the input digest, steps, digests and parameters from the fake."""
    _, end, trace = run(5, [1, 2, 3])
    assert trace.input_digest == 5 and trace.final_digest == end.digest == 11
    assert trace.steps == (Step("add", (1,)), Step("add", (2,)), Step("add", (3,)))
    assert trace.digests == (6, 8, 11)
    assert trace.parameter("fake") is True


# -- replay -----------------------------------------------------------------------------------
@FEW
@given(st.integers(0, 100), additions)
def test_replay_reproduces_the_run_in_one_transient(start: int, ks: list[int]) -> None:
    """replay gives the recorded end from the start, opening a single transient."""
    mesh, end, trace = run(start, ks)
    OPENED.clear()
    result = replay(mesh, trace)
    assert result == end and result.value == start + sum(ks)
    assert len(OPENED) == 1 and OPENED[0].sealed
    assert mesh == Counter(start)


@FEW
@given(st.integers(0, 100), additions, st.data())
def test_replay_until_stops_after_that_many_steps(
    start: int, ks: list[int], data: st.DataObject
) -> None:
    """replay(…, until=k) is the mesh after the first k steps (k = 0: the start)."""
    mesh, _, trace = run(start, ks)
    until = data.draw(st.integers(0, len(ks)))
    assert replay(mesh, trace, until=until) == Counter(start + sum(ks[:until]))


@FEW
@given(st.integers(0, 100), additions)
def test_replay_iter_yields_every_intermediate_snapshot(start: int, ks: list[int]) -> None:
    """replay_iter yields the mesh after each step, with the recorded digests, each step in
    its own transient."""
    mesh, end, trace = run(start, ks)
    OPENED.clear()
    meshes = list(replay_iter(mesh, trace))
    assert [m.digest for m in meshes] == list(trace.digests)
    assert meshes[-1:] == ([end] if ks else [])
    assert len(OPENED) == len(ks) and all(t.sealed for t in OPENED)
    assert list(replay_iter(mesh, trace, until=len(ks) // 2)) == meshes[: len(ks) // 2]


def test_replay_of_an_empty_trace_is_the_start() -> None:
    """A trace without steps replays to a mesh equal to the start."""
    mesh, _, trace = run(4, [])
    assert replay(mesh, trace) == mesh
    assert list(replay_iter(mesh, trace)) == []


# -- errors -----------------------------------------------------------------------------------
def test_replay_refuses_a_start_that_is_not_the_input() -> None:
    """A start whose digest is not the trace's input digest is refused before any step,
    by replay, replay_iter and check_start, with no step number."""
    _, _, trace = run(3, [1, 1])
    OPENED.clear()
    for attempt in (lambda: replay(Counter(4), trace),
                    lambda: next(replay_iter(Counter(4), trace)),
                    lambda: check_start(Counter(4), trace)):
        with pytest.raises(TraceError, match="not the trace's input") as caught:
            attempt()
        assert caught.value.step is None
    assert OPENED == []  # refused before opening a transient
    check_start(Counter(3), trace)


def test_replay_names_the_step_whose_digest_diverges() -> None:
    """A recorded digest that the replay does not reproduce raises TraceError naming that
    step (1-based) and both digests; replay_iter has yielded the steps before it."""
    start, _, trace = run(0, [1, 2, 3, 4])
    tampered = Trace(trace.input_digest, trace.steps, (1, 3, 99, 10))
    with pytest.raises(TraceError, match=r"step 3 \(add\(3\)\)") as caught:
        replay(start, tampered)
    assert caught.value.step == 3
    assert f"{6:032x}" in str(caught.value) and f"{99:032x}" in str(caught.value)
    yielded = []
    with pytest.raises(TraceError) as caught:
        for mesh in replay_iter(start, tampered):
            yielded.append(mesh)
    assert yielded == [Counter(1), Counter(3)] and caught.value.step == 3
    assert replay(start, tampered, until=2) == Counter(3)


@pytest.mark.parametrize(
    ("step", "message"),
    [(Step("add", (-10,)), "negative"), (Step("multiply", (2,)), "unknown step")],
)
def test_replay_names_a_step_that_cannot_be_applied(step: Step, message: str) -> None:
    """A step the transient refuses with ValueError becomes a TraceError naming the step,
    chained to the refusal."""
    start, _, trace = run(2, [1, 1])
    broken = Trace(2, (*trace.steps, step), (*trace.digests, 0))
    with pytest.raises(TraceError, match=f"step 3 .*cannot be applied.*{message}") as caught:
        replay(start, broken)
    assert caught.value.step == 3
    assert isinstance(caught.value.__cause__, ValueError)
    with pytest.raises(TraceError, match="cannot be applied"):
        list(replay_iter(start, broken))


@pytest.mark.parametrize("until", [-1, 4, 100])
def test_until_outside_the_trace_is_refused(until: int) -> None:
    """until must lie in 0..len(trace), for replay and replay_iter."""
    start, _, trace = run(0, [1, 2, 3])
    with pytest.raises(TraceError, match=f"{until} is outside 0..3"):
        replay(start, trace, until=until)
    with pytest.raises(TraceError, match="outside"):
        list(replay_iter(start, trace, until=until))


def test_errors_of_the_transient_other_than_value_errors_propagate() -> None:
    """Only a refusal (ValueError) is turned into a TraceError: any other error from the
    transient propagates unchanged."""

    class Broken(CounterTransient):
        def apply(self, step: Step, /) -> None:
            raise KeyError("internal")

    @attrs.frozen
    class BrokenCounter(Counter):
        def transient(self, *, batch: bool = False) -> CounterTransient:
            return Broken(self.value)

    _, _, trace = run(0, [1])
    with pytest.raises(KeyError):
        replay(BrokenCounter(0), trace)


# -- divergence -------------------------------------------------------------------------------
def test_first_divergence() -> None:
    """None for identical traces; 0 for different inputs; the first index where a step or a
    digest differs; the shorter length for a prefix; symmetric."""
    _, _, base = run(0, [1, 2, 3])
    _, _, same = run(0, [1, 2, 3])
    _, _, other_input = run(1, [1, 2, 3])
    _, _, other_step = run(0, [1, 5, 3])
    _, _, prefix = run(0, [1, 2])
    other_digest = Trace(base.input_digest, base.steps, (1, 3, 7))
    assert first_divergence(base, same) is None
    assert first_divergence(base, other_input) == 0
    assert first_divergence(base, other_step) == 1
    assert first_divergence(base, other_digest) == 2
    assert first_divergence(base, prefix) == 2 == first_divergence(prefix, base)
    for other in (other_input, other_step, other_digest, prefix):
        assert first_divergence(base, other) == first_divergence(other, base)


@FEW
@given(st.integers(0, 20), additions, additions)
def test_first_divergence_is_the_length_of_the_common_prefix(
    start: int, ks: list[int], ls: list[int]
) -> None:
    """For two runs from the same start the divergence index is where their steps first
    differ (None when they are the same run), and replaying that many steps of either
    gives the same mesh."""
    mesh, _, a = run(start, ks)
    _, _, b = run(start, ls)
    common = 0
    while common < min(len(ks), len(ls)) and ks[common] == ls[common]:
        common += 1
    expected = None if ks == ls else common
    assert first_divergence(a, b) == expected
    assert replay(mesh, a, until=common) == replay(mesh, b, until=common)
