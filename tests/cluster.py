"""A lecture on several processes for tests, with the real parts: redis-server and nginx on free
ports, N app workers (`create_server(..., redis_url=, worker_id=)`) in this process, so a test
reads their state, behind nginx's `least_conn` (`app.launch.nginx_config`).

    from cluster import Cluster, cluster_fixture
    cluster = cluster_fixture(workers=2)          # a module-scoped fixture named `cluster`

    def test_x(cluster: Cluster) -> None:
        client = RawClient(cluster.port)          # through nginx
        session, worker = cluster.session_of(...)  # or cluster.apps[k].sessions
        cluster.stop_worker(1)                     # as if it died: its browsers lose their websockets

Skips (pytest.skip) when nginx or redis-server is not installed (`.ci/run` installs both).
`Cluster.reset()` empties Redis's `rbl:` keys between tests that share one cluster.
"""

from __future__ import annotations

import shutil
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from app.cluster import KEY_PREFIX, connect
from app.cluster.services import MissingProgram, free_port, require, start_redis, stop_process
from app.launch import start_nginx

__all__ = ["CODE", "Cluster", "cluster_fixture", "missing_parts"]

CODE = "1357 2468"  # the presenter code of every test cluster


def missing_parts() -> str | None:
    """Why a cluster cannot start here (nginx or redis-server missing), or None."""
    for program in ("nginx", "redis-server"):
        try:
            require(program)
        except MissingProgram as error:
            return str(error)
    return None


class Cluster:
    """Redis, `workers` in-process apps and nginx in front of them; `close` stops everything.

    Attributes:
        redis_url: the Redis (password-protected, localhost).  redis: a client of it.
        apps: the workers (`app.main.App`), worker ids "w1", "w2", ...
        port: nginx's port (what a browser opens).  folder: nginx's files.
    """

    def __init__(self, workers: int = 2, *, code: str = CODE, start_loop: bool = True, **options: Any) -> None:
        from app.main import create_server

        self.code = code
        self.folder = Path(tempfile.mkdtemp(prefix="rbl-cluster-"))
        self.redis_process: Any = None
        self.nginx: Any = None
        self.apps: list[Any] = []
        self.clients: list[Any] = []  # `join`'s, closed by `close`
        try:
            self.redis_url, self.redis_process = start_redis(password="test-password-" + self.folder.name[-6:])
            self.redis = connect(self.redis_url)
            for k in range(1, workers + 1):
                self.apps.append(create_server("127.0.0.1", 0, verbose=False, start_loop=start_loop,
                                               presenter_code=code, redis_url=self.redis_url, worker_id=f"w{k}",
                                               **options))
            self.port = free_port()
            self.nginx = start_nginx("127.0.0.1", self.port, [f"127.0.0.1:{a.port}" for a in self.apps],
                                     self.folder, worker_processes="1")
        except BaseException:
            self.close()
            raise

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    def join(self, timeout: float = 20.0) -> tuple[Any, int, Any]:
        """One more browser stand-in (`benchmarks.ws_client.ViserClient`) through nginx: (the
        client, the index of the worker it reached, its session there)."""
        import time

        from benchmarks.ws_client import ViserClient

        before = {id(session) for _, session in self.sessions()}
        client = ViserClient(self.port)
        self.clients.append(client)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for index, session in self.sessions():
                if id(session) not in before and session.lecture is not None:
                    client.wait_for_label("Present", timeout=timeout)
                    return client, index, session
            time.sleep(0.02)
        raise TimeoutError(f"no new session within {timeout} s")

    def worker_of(self, client_id_session: Any) -> int:
        """The index in `apps` of the worker that holds this session."""
        for index, app in enumerate(self.apps):
            if any(session is client_id_session for session in list(app.sessions.values())):
                return index
        raise LookupError("no worker holds this session")

    def sessions(self) -> list[tuple[int, Any]]:
        """(worker index, session) of every open session on every running worker."""
        return [(index, session) for index, app in enumerate(self.apps) if app is not None
                for session in list(app.sessions.values())]

    def total_sessions(self) -> int:
        return sum(len(app.sessions) for app in self.apps if app is not None)

    def stop_worker(self, index: int) -> None:
        """Stop worker `index` (its server and loop; its lock's lease lapses or is released)."""
        app, self.apps[index] = self.apps[index], None
        if app is not None:
            app.stop()

    def reset(self) -> None:
        """Forget the lecture's state in Redis (keys `rbl:*`): no presenter, no wrong codes counted."""
        keys = list(self.redis.scan_iter(match=KEY_PREFIX + "*"))
        if keys:
            self.redis.delete(*keys)

    def close_clients(self) -> None:
        for client in self.clients:
            client.close()
        self.clients = []

    def close(self) -> None:
        self.close_clients()
        stop_process(self.nginx)
        for app in self.apps:
            if app is not None:
                app.stop()
        redis = getattr(self, "redis", None)
        if redis is not None:
            redis.close()
        stop_process(self.redis_process)
        shutil.rmtree(self.folder, ignore_errors=True)


def cluster_fixture(workers: int = 2, name: str = "cluster", **options: Any) -> Callable[..., Iterator[Cluster]]:
    """A module-scoped pytest fixture `name` giving a running Cluster (skipped without nginx or
    redis-server); bind it to a module-level name: `cluster = cluster_fixture(2)`."""

    @pytest.fixture(scope="module", name=name)
    def _cluster() -> Iterator[Cluster]:
        why = missing_parts()
        if why is not None:
            pytest.skip(why)
        running = Cluster(workers, **options)
        try:
            yield running
        finally:
            running.close()

    return _cluster
