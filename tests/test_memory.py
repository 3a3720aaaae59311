"""What a browser held ends with it: browsers join and leave a lecture with the collector tuned as
the command line tunes it (`app.main.tune_collector`), and afterwards the server holds no more
than before: no session object of a browser that left (not even as garbage awaiting a full
pass of the collector) and no entry under its client id in the lectern (issue 34, row 10)."""

from __future__ import annotations

import gc
import time
import weakref
from collections.abc import Iterator
from typing import Any

import pytest

from app.lecture.lectern import Mode
from app.main import App, create_server, tune_collector
from app.session import Session
from app.sweep import RETRIES, Sweep
from tests.conftest import RawClient

CODE = "271828"
JOINS = 24  # browsers that join, follow the presenter and leave
AT_ONCE = 4  # of them connected at the same time
SWEEPS = 3  # full passes after the last one left within which every departed session is freed
SWEPT_WITHIN_S = 240.0  # [s] for those passes: on a busy machine a pass takes ~1 s and the next
#                         waits COST_FACTOR times that (app.sweep), so three passes can take minutes


@pytest.fixture
def served() -> Iterator[App]:
    """The app with the garbage collector tuned as `python -m app` tunes it (restored after)."""
    thresholds = gc.get_threshold()
    tune_collector()
    running = create_server("127.0.0.1", 0, verbose=False, presenter_code=CODE)
    try:
        yield running
    finally:
        running.stop()
        gc.unfreeze()
        gc.set_threshold(*thresholds)


def sessions_in_memory() -> int:
    """Session objects in this process, reachable or not (garbage not yet collected counts; the
    test never collects)."""
    return sum(1 for thing in gc.get_objects() if type(thing) is Session)


def kept_by(presenter: Session) -> str:
    """What refers to a session other than `presenter` still in memory (the failure message)."""
    left = [thing for thing in gc.get_objects() if type(thing) is Session and thing is not presenter]
    if not left:
        return "none left"
    holders = [type(holder).__qualname__ for holder in gc.get_referrers(left[0]) if holder is not left]
    return f"one of them is referred to by {holders}"


def per_client_entries(app: App) -> dict[str, int]:
    """Entries the lectern's parts keep by client id, by structure."""
    lectern: Any = app.lectern
    kept = {"follower_panels": ("_followers", "_watched"),
            "presenter_lock": ("_tries", "_refused", "_hall_wait", "_refusal_watchers"), "seating": ("_called",)}
    return {f"{part}.{name}": len(getattr(getattr(lectern, part), name)) for part, names in kept.items()
            for name in names}


def wait_for(predicate: Any, timeout: float, what: str, seen: Any = lambda: None) -> None:
    """Poll `predicate()` until true; AssertionError naming `what` and what `seen()` says if not
    within `timeout` [s]."""
    deadline = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > deadline:
            raise AssertionError(f"waited {timeout} s for {what}; saw {seen()}")
        time.sleep(0.1)


@pytest.mark.timeout(480)  # SWEPT_WITHIN_S after the joins, on a busy machine
def test_browsers_that_followed_and_left_leave_no_session_and_no_entry(served: App) -> None:
    app = served
    presenter_client = RawClient(app.port)
    try:
        (presenter,) = app.wait_for_sessions(1, timeout=30.0).values()
        presenter.present(CODE)
        presenter.play()
        before = per_client_entries(app)
        for first in range(0, JOINS, AT_ONCE):
            group = [RawClient(app.port) for _ in range(AT_ONCE)]
            sessions = app.wait_for_sessions(1 + AT_ONCE, timeout=30.0)
            joined = [s for s in sessions.values() if s is not presenter]
            wait_for(lambda j=joined: all(s.mode is Mode.FOLLOWING for s in j), 30.0,
                     f"browsers {first + 1}..{first + AT_ONCE} to follow the presenter",
                     lambda j=joined: [s.mode.name for s in j])
            for client in group:
                client.close()
            app.wait_for_sessions(1, timeout=30.0)
            del sessions, joined  # this test holds none of them
        left = per_client_entries(app)
        assert left == before, f"entries by client id before {JOINS} browsers came and went: {before}; after: {left}"
        passes_then = app.sweep.passes
        wait_for(lambda: sessions_in_memory() == 1 or app.sweep.passes >= passes_then + SWEEPS, SWEPT_WITHIN_S,
                 f"the sessions of the {JOINS} browsers that left to be freed, or {SWEEPS} sweeps",
                 lambda: f"{sessions_in_memory()} Session objects in memory, {app.sweep.passes} sweeps, "
                         f"{app.sweep.owed} browsers owed one; {kept_by(presenter)}")
        assert sessions_in_memory() == 1, (f"{sessions_in_memory() - 1} sessions of browsers that left are alive after "
                                           f"{app.sweep.passes - passes_then} sweeps; {kept_by(presenter)}")
        assert app.sweep.passes >= 1
        print(f"sweeps: {app.sweep.passes}, longest {app.sweep.longest * 1e3:.0f} ms")
    finally:
        presenter_client.close()


def test_a_sweep_runs_only_after_a_departure_and_at_most_as_often_as_its_cost_allows() -> None:
    now = [100.0]
    took = [0.0]

    def collect() -> int:
        now[0] += took[0]
        return 0

    sweep = Sweep(min_interval_s=5.0, cost_factor=50.0, clock=lambda: now[0], collect=collect)
    assert not sweep.run_if_due(), "nobody left: no pass"
    sweep.left()
    took[0] = 0.25  # a pass of 0.25 s: the next one not before 50 x 0.25 = 12.5 s after it
    assert sweep.run_if_due() and sweep.passes == 1 and sweep.owed == 0
    sweep.left()
    now[0] += 12.0
    assert not sweep.run_if_due(), "12 s after a 0.25 s pass: too soon"
    now[0] += 0.5
    took[0] = 0.0625
    assert sweep.run_if_due() and sweep.passes == 2
    now[0] += 20.0
    assert not sweep.run_if_due(), "nobody left since the last pass"
    sweep.left()
    assert sweep.run_if_due() and sweep.passes == 3, "a departure long after the last pass: at once"
    sweep.left()
    now[0] += 4.5
    assert not sweep.run_if_due(), "4.5 s after a 0.0625 s pass: within the minimum interval"
    now[0] += 0.5
    assert sweep.run_if_due() and sweep.passes == 4
    assert sweep.longest == 0.25 and sweep.seconds == 0.4375


def test_a_departure_still_held_during_a_pass_stays_owed_until_a_pass_frees_it() -> None:
    """A session a closing thread still holds while the pass runs is swept by a later pass (the
    race seen under load: one departed Session kept for good, no departure left to owe a pass)."""
    now = [0.0]

    class Departed:
        pass

    holder: list[Departed] = [Departed()]
    gone = weakref.ref(holder[0])
    sweep = Sweep(min_interval_s=5.0, cost_factor=50.0, clock=lambda: now[0], collect=gc.collect)
    sweep.left(holder[0])
    assert sweep.run_if_due() and gone() is not None
    assert sweep.owed == 1, "a departure a pass found alive is owed another pass"
    holder.clear()  # the closing thread lets go
    assert not sweep.run_if_due(), "no pass before min_interval_s"
    now[0] += 5.0
    assert sweep.run_if_due() and sweep.owed == 0 and gone() is None
    leak = Departed()
    sweep.left(leak)
    for _ in range(RETRIES):
        now[0] += 5.0
        assert sweep.run_if_due()
    now[0] += 5.0
    assert not sweep.run_if_due(), f"a departure kept alive for good is owed {RETRIES} passes, no more"
