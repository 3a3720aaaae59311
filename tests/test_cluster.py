"""Two workers behind the real nginx, one Redis (`tests/cluster.py`, one cluster for the module):
the page and the websockets through nginx, spread over both workers; one presenter across
workers; a right code answers as a wrong one while someone presents; wrong codes limited over
the whole hall; the lecturer gets in within a minute of an attack; a worker that ends leaves the
other's browsers working (last: it breaks the cluster).  Browsers are websocket clients that
type and click as a browser does (`benchmarks.ws_client.ViserClient`); the servers' state is
read to check."""

from __future__ import annotations

import urllib.request
from typing import Any

from cluster import CODE, Cluster, cluster_fixture
from conftest import poll_until

from app.lecture.gate import RedisGate

cluster = cluster_fixture(workers=2)

BUSY = "Someone else is presenting; they must stop first."


def _note(session: Any) -> str:
    return str(session.lecture.gui_note.content)


def _try(client: Any, session: Any, code: str, expect: str, timeout: float = 30.0) -> str:
    """Type `code` into the browser's `Presenter code`, press `Present`; the panel's note once the
    server has answered (it must contain `expect`; "": the browser presents)."""
    if not hasattr(session, "tries_answered"):  # count the server's answers (the button calls `present`)
        present = session.present
        session.tries_answered = 0

        def counted(typed: str) -> None:
            try:
                present(typed)
            finally:
                session.tries_answered += 1

        session.present = counted
    answered = session.tries_answered
    client.set_value("Presenter code", code)
    poll_until(lambda: session.lecture.gui_code.value == code, timeout)
    client.click("Present")
    poll_until(lambda: session.tries_answered > answered, timeout)
    if expect == "":
        assert session.mode == "presenting", (_note(session), session.last_error)
        return ""
    assert expect in _note(session) and session.mode != "presenting"
    return _note(session)


def _on_both(cluster: Cluster, count: int) -> list[tuple[Any, int, Any]]:
    joined = [cluster.join() for _ in range(count)]
    assert {index for _, index, _ in joined} == {0, 1}, "least_conn put every websocket on one worker"
    return joined


def test_the_page_and_the_websockets_go_through_nginx_spread_over_both_workers(cluster: Cluster) -> None:
    with urllib.request.urlopen(cluster.url, timeout=10) as response:  # noqa: S310 - loopback
        page = response.read().decode()
    assert response.status == 200 and "<!doctype html>" in page.lower()
    joined = [cluster.join() for _ in range(4)]
    per_worker = [sum(1 for _, index, _ in joined if index == k) for k in (0, 1)]
    assert per_worker == [2, 2]  # least connections, not one address's worker
    client, _, session = joined[0]
    client.click("Play")  # a browser's own room lives in the worker its websocket reached
    poll_until(lambda: session.room.playing and session.simulation.t > 0.2, 10.0)
    cluster.close_clients()
    poll_until(lambda: cluster.total_sessions() == 0, 10.0)


def test_two_browsers_on_two_workers_cannot_both_present(cluster: Cluster) -> None:
    cluster.reset()
    (a, wa, sa), (b, wb, sb) = _on_both(cluster, 2)
    _try(a, sa, CODE, "")
    holder = cluster.apps[wa].lectern.gate.presenter()
    assert holder == f"w{wa + 1}:{sa.client_id}"
    # On the other worker, the right code and a wrong one get the same answer, and neither is evaluated.
    assert _try(b, sb, CODE.replace(" ", "-"), BUSY).endswith(BUSY + "**")
    # (b follows the new presenter by default once its worker hears of it: own or following, not presenting)
    assert sb.mode != "presenting" and int(cluster.redis.zcard("rbl:gate:wrong")) == 0
    assert _try(b, sb, "0000 0000", BUSY).endswith(BUSY + "**")
    assert int(cluster.redis.zcard("rbl:gate:wrong")) == 0
    a.click("Stop presenting")
    poll_until(lambda: sa.mode == "own" and cluster.apps[wa].lectern.gate.presenter() is None, 10.0)
    poll_until(lambda: _note(sb) == "", 10.0)  # "someone else is presenting" goes when they stop
    _try(b, sb, CODE.replace(" ", ""), "")  # typed without its space
    assert cluster.apps[wb].lectern.gate.presenter() == f"w{wb + 1}:{sb.client_id}"
    b.close()  # the presenter's tab closes: the lock is free at once
    poll_until(lambda: cluster.apps[wa].lectern.gate.presenter() is None, 10.0)
    cluster.close_clients()
    poll_until(lambda: cluster.total_sessions() == 0, 10.0)


def test_wrong_codes_are_limited_over_the_hall_and_the_lecturer_gets_in_after_the_attack(cluster: Cluster) -> None:
    cluster.reset()
    clock = [1000.0]  # [s] the window's clock, advanced by the test
    gates = []
    for k, app in enumerate(cluster.apps):  # the hall's limit made small: 6 wrong codes a minute
        gate = RedisGate(cluster.redis_url, f"w{k + 1}", CODE, clock=lambda: clock[0], max_wrong=6)
        gates.append((app.lectern, app.lectern.gate))
        app.lectern.gate = gate
    try:
        joined = _on_both(cluster, 4)
        for round_ in range(2):  # 4 browsers on 2 workers, 2 wrong codes each: 8 tries, 6 evaluated
            for client, _, session in joined:
                words = "Wrong presenter code" if int(cluster.redis.zcard("rbl:gate:wrong")) < 6 else "lecture hall"
                _try(client, session, f"9999 00{round_}{session.client_id % 10}", words)
        assert int(cluster.redis.zcard("rbl:gate:wrong")) == 6
        hall_words = [_note(session) for _, _, session in joined]
        assert sum("Too many wrong codes in this lecture hall" in words for words in hall_words) == 2
        # The lecturer, on either worker, with the right code: the same answer, not evaluated.
        lecturer, _, session = cluster.join()
        assert "in this lecture hall" in _try(lecturer, session, CODE, "in this lecture hall")
        clock[0] += 61.0  # the attack stopped a minute ago: the window is empty
        _try(lecturer, session, CODE, "")
        assert session.mode == "presenting"
    finally:
        for lectern, gate in gates:
            lectern.gate.close()
            lectern.gate = gate
        cluster.close_clients()
        poll_until(lambda: cluster.total_sessions() == 0, 10.0)


def test_a_worker_that_ends_leaves_the_others_browsers_working(cluster: Cluster) -> None:
    cluster.reset()
    (a, wa, sa), (b, wb, sb) = _on_both(cluster, 2)
    _try(a, sa, CODE, "")  # the presenter is on the worker that ends
    cluster.stop_worker(wa)
    assert cluster.redis.get("rbl:presenter") is None  # released as it stopped
    if sb.mode == "following":  # the last state an earlier presenter on its worker left
        b.wait_for_label("Explore on my own", 30.0)  # the follower's panel reaches the client after the mode
        b.click("Explore on my own")
        poll_until(lambda: sb.mode == "own", 10.0)
    b.wait_for_label("Play")
    b.click("Play")
    t0 = sb.simulation.t
    poll_until(lambda: sb.room.playing and sb.simulation.t > t0 + 0.2, 10.0)
    c, wc, sc = cluster.join()  # nginx sends a new browser to the worker that answers
    assert wc == wb
    _try(c, sc, CODE, "")  # and the lock is free for a new presenter there
