"""The presenter lock nobody guesses (`app.lecture.gate`), in one process (`LocalGate`, through
the `Lectern` as the app uses it) and in Redis (`RedisGate`, a real redis-server on a free port):
the chance a limited guesser has, one answer for every code while someone presents, wrong codes
limited over all browsers, the lecturer in within a minute of an attack, a lease that lapses
when its process dies."""

from __future__ import annotations

from collections.abc import Iterator
from types import SimpleNamespace
from typing import Any

import pytest
from cluster import missing_parts

from app.cluster.services import start_redis, stop_process
from app.lecture.gate import (
    LEASE_S,
    MAX_WRONG,
    WINDOW_S,
    LocalGate,
    RedisGate,
    Verdict,
    code_matches,
    guess_chance,
    new_code,
)
from app.lecture.lectern import MAX_TRIES, Lectern

CODE = "4821 0937"
BUSY = "Someone else is presenting; they must stop first."


def _browser(client_id: int) -> Any:
    return SimpleNamespace(client_id=client_id, closed=False)


def test_a_random_code_has_at_most_1e_4_chance_in_a_90_minute_lecture() -> None:
    code = new_code()
    assert len(code) == 9 and code[4] == " " and code.replace(" ", "").isdigit()
    assert guess_chance(90.0) == pytest.approx(MAX_WRONG * 90 / 1e8) and guess_chance(90.0) <= 1e-4
    assert guess_chance(90.0, "123456") > 1e-3  # the six digits of before: 0.54 %
    assert code_matches("4821-0937", CODE) and code_matches(" 48210937 ", CODE) and code_matches("4821 – 0937", CODE)
    assert not code_matches("4821 0938", CODE) and not code_matches("", CODE)


def test_wrong_codes_are_limited_over_all_browsers_and_the_lecturer_gets_in_a_minute_after() -> None:
    clock = [0.0]
    lectern = Lectern(server=None, code=CODE, clock=lambda: clock[0])  # type: ignore[arg-type]
    attackers = [_browser(100 + k) for k in range(MAX_WRONG // MAX_TRIES + 2)]
    evaluated = 0
    for browser in attackers:  # each browser stays within its own MAX_TRIES
        for k in range(MAX_TRIES):
            words = lectern.try_code(browser, f"1111 {browser.client_id}{k}")
            evaluated += str(words).startswith("Wrong presenter code")
            clock[0] += 0.1
    assert evaluated == MAX_WRONG  # the hall's limit, not the browsers'
    lecturer = _browser(1)
    words = lectern.try_code(lecturer, CODE)  # the right code is not evaluated either
    assert words is not None and "Too many wrong codes in this lecture hall" in words
    assert words == lectern.try_code(lecturer, "0000 0000")  # a wrong code: the same answer
    assert lectern.refusal_now(lecturer) is not None
    clock[0] = 1.0 + WINDOW_S  # a minute after the first wrong code: slots free again
    assert lectern.try_code(lecturer, CODE.replace(" ", "-")) is None


def test_while_someone_presents_every_code_gets_one_answer_and_is_not_evaluated() -> None:
    clock = [0.0]
    gate = LocalGate(CODE, lambda: clock[0])
    lectern = Lectern(server=None, clock=lambda: clock[0], gate=gate)  # type: ignore[arg-type]
    assert lectern.code == CODE
    presenter, guesser = _browser(1), _browser(2)
    assert lectern.try_code(presenter, CODE) is None and gate.start("local:1")
    clock[0] = 10 * LEASE_S  # a started lock has no lease in one process: held until released
    answers = {lectern.try_code(guesser, code) for code in (CODE, "0000 0000", "4821-0937", "")}
    assert answers == {BUSY}
    assert not gate._wrong  # nothing evaluated, nothing counted
    gate.release("local:1")
    assert lectern.refusal_now(guesser) is None  # the note goes when they stop
    assert lectern.try_code(guesser, CODE) is None


@pytest.fixture(scope="module")
def redis_url() -> Iterator[str]:
    if missing_parts() is not None:
        pytest.skip(str(missing_parts()))
    url, process = start_redis(password="gate-test")
    try:
        yield url
    finally:
        stop_process(process)


def test_redis_gate_one_presenter_over_workers_and_a_lease_that_lapses(redis_url: str) -> None:
    clock = [5000.0]
    one = RedisGate(redis_url, "w1", CODE, clock=lambda: clock[0], lease_s=0.3, presenter_cache_s=0.0)
    two = RedisGate(redis_url, "w2", CODE, clock=lambda: clock[0], lease_s=0.3, presenter_cache_s=0.0)
    try:
        one._redis.delete("rbl:presenter", "rbl:gate:wrong")
        assert one.claim("w1:1", "0000 0000").verdict is Verdict.WRONG
        assert one.claim("w1:1", "48210937").verdict is Verdict.OK and one.start("w1:1")
        assert two.presenter() == "w1:1"
        # Right and wrong: one answer, nothing counted.
        assert {two.claim("w2:5", code).verdict for code in (CODE, "1")} == {Verdict.BUSY}
        assert int(one._redis.zcard("rbl:gate:wrong")) == 1
        assert one.renew("w1:1") and not two.renew("w2:5")
        # w1 dies (stops renewing): within the lease the lock is free for w2.
        import time

        deadline = time.monotonic() + 5.0
        while two.presenter() is not None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert two.presenter() is None
        assert two.claim("w2:5", CODE).verdict is Verdict.OK
        assert not one.renew("w1:1")  # the old holder cannot take it back
        two.release("w1:1")  # not its holder: nothing happens
        assert one.presenter() == "w2:5"
        two.close()  # a worker that stops frees what it holds
        assert one.presenter() is None
    finally:
        one.close()


def test_redis_gate_counts_wrong_codes_over_workers_in_a_sliding_window(redis_url: str) -> None:
    clock = [9000.0]
    gates = [RedisGate(redis_url, f"w{k}", CODE, clock=lambda: clock[0], max_wrong=4) for k in (1, 2)]
    try:
        gates[0]._redis.delete("rbl:presenter", "rbl:gate:wrong")
        verdicts = []
        for k in range(6):
            verdicts.append(gates[k % 2].claim(f"w{k % 2 + 1}:{k}", f"9{k}").verdict)
            clock[0] += 1.0
        assert verdicts == [Verdict.WRONG] * 4 + [Verdict.WAIT] * 2
        answer = gates[1].claim("w2:99", CODE)
        assert answer.verdict is Verdict.WAIT and answer.wait_s == pytest.approx(WINDOW_S - 6.0)
        clock[0] += answer.wait_s  # the oldest wrong code leaves the window: one slot
        assert gates[1].claim("w2:99", CODE).verdict is Verdict.OK
        assert int(gates[0]._redis.zcard("rbl:gate:wrong")) == 3  # the right code took its count back
    finally:
        for gate in gates:
            gate.close()


def test_a_presenter_whose_lock_someone_else_took_stops_presenting() -> None:
    clock = [0.0]
    gate = LocalGate(CODE, lambda: clock[0])
    lectern = Lectern(server=None, clock=lambda: clock[0], gate=gate)  # type: ignore[arg-type]
    stopped: list[str] = []
    seat = SimpleNamespace(client_id=1, closed=False, guard=lambda _where, fn: fn,
                           stop_presenting=lambda: stopped.append("stopped"), report_error=lambda *_: None)
    lectern.presenter = seat  # type: ignore[assignment]
    assert gate.claim("w9:9", CODE).verdict is Verdict.OK  # e.g. after a lapse, on another process
    lectern.tick(1.0)  # the loop renews about every second
    assert stopped == ["stopped"]


def test_the_one_process_app_imports_no_redis() -> None:
    """`import redis` stands only inside functions (`app.cluster.connect`), which only a worker calls."""
    import ast
    from pathlib import Path

    root = Path(__file__).resolve().parents[1] / "app"
    for path in root.rglob("*.py"):
        todo = [(node, False) for node in ast.parse(path.read_text(encoding="utf-8")).body]
        while todo:  # (node, inside a function)
            node, inside = todo.pop()
            names = ([alias.name for alias in node.names] if isinstance(node, ast.Import) else
                     [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            if any(name.split(".")[0] == "redis" for name in names):
                assert inside, f"{path}: redis imported at module level"
            nested = inside or isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)
            todo.extend((child, nested) for child in ast.iter_child_nodes(node))


def test_a_lock_that_does_not_answer_is_said_and_changes_nothing() -> None:
    from app.cluster.services import free_port

    clock = [0.0]
    gate = RedisGate(f"redis://127.0.0.1:{free_port()}/0", "w1", CODE, clock=lambda: clock[0])  # nothing there
    lectern = Lectern(server=None, clock=lambda: clock[0], gate=gate)  # type: ignore[arg-type]
    browser = _browser(3)
    words = lectern.try_code(browser, CODE)
    assert words is not None and "does not answer" in words and lectern.presenter is None
    clock[0] = 11.0
    assert lectern.refusal_now(browser) is None  # said for a while; then the browser may try again
    lectern.close()
