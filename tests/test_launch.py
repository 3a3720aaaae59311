"""`rigid-body-lab --workers N` as a person starts it (a subprocess): the page and a websocket
through nginx, one code printed once, a worker that dies is reported and the others go on,
Ctrl-C and SIGTERM leave nothing running; nginx's configuration; a missing nginx or redis-server
named at start with the command that installs it."""

from __future__ import annotations

import argparse
import os
import re
import shutil
import signal
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest
from cluster import missing_parts
from conftest import poll_until

from app.cluster import services
from app.cluster.services import free_port
from app.launch import launch_main, nginx_config
from app.main import main as app_main

ROOT = Path(__file__).resolve().parents[1]


def _children(pid: int) -> set[int]:
    """Every descendant of `pid` alive now (Linux /proc)."""
    found: set[int] = set()
    todo = [pid]
    while todo:
        parent = todo.pop()
        for task in Path(f"/proc/{parent}/task").glob("*"):
            try:
                kids = {int(k) for k in (task / "children").read_text().split()}
            except OSError:
                continue
            todo.extend(kids - found)
            found |= kids
    return found


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().split(")")[-1].split()[0]
    except OSError:
        return False
    return state != "Z"


class Launched:
    """`python -m app --port P ARGS` in a subprocess, its output in files; `started()` waits for its line."""

    def __init__(self, *args: str) -> None:
        self.port = free_port()
        self.folder = Path(os.environ.get("TMPDIR", "/tmp"))
        self.out = open(self.folder / f"rbl-launch-{self.port}.out", "w+b")  # noqa: SIM115
        self.err = open(self.folder / f"rbl-launch-{self.port}.err", "w+b")  # noqa: SIM115
        # a data folder of its own: two launches at once on one folder share its Redis's append-only
        # directory, and the second redis-server exits (seen in a fresh-clone run)
        own = () if "--data-dir" in args else ("--data-dir", str(self.folder / f"rbl-launch-{self.port}-data"))
        self.process = subprocess.Popen([sys.executable, "-m", "app", "--port", str(self.port), *args, *own],
                                        cwd=ROOT, stdout=self.out, stderr=self.err)

    def started(self) -> None:
        poll_until(lambda: "open http" in self.stdout() or self.process.poll() is not None, 120.0, 0.1)
        assert self.process.poll() is None, self.stderr()

    def stdout(self) -> str:
        return (self.folder / f"rbl-launch-{self.port}.out").read_text(errors="replace")

    def stderr(self) -> str:
        return (self.folder / f"rbl-launch-{self.port}.err").read_text(errors="replace")

    def close(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait(10)
        kept = re.search(r"the workers' logs stay in (\S+)", self.stderr())  # after a worker died
        if kept and Path(kept.group(1)).name.startswith("rigid-body-lab-"):
            shutil.rmtree(kept.group(1), ignore_errors=True)
        for name in ("out", "err"):
            getattr(self, name).close()
            (self.folder / f"rbl-launch-{self.port}.{name}").unlink(missing_ok=True)


needs_parts = pytest.mark.skipif(missing_parts() is not None, reason=str(missing_parts()))


@needs_parts
def test_workers_behind_nginx_a_dead_worker_is_reported_ctrl_c_and_sigterm_stop_everything() -> None:
    from benchmarks.ws_client import ViserClient

    # Two launches at once (they start in parallel): one stopped by Ctrl-C, one by SIGTERM.
    launched = Launched("--workers", "2", "--presenter-code", "2468 1357")
    termed = Launched("--workers", "1")
    try:
        launched.started()
        termed.started()
        out = launched.stdout()
        assert out.count("presenter code: 2468 1357") == 1 and "2 workers" in out
        assert "presenter code: " in termed.stdout()
        children = _children(launched.process.pid)
        assert len(children) >= 4  # redis, 2 workers, nginx (and nginx's own workers)
        term_children = _children(termed.process.pid)
        assert len(term_children) >= 3
        termed.process.send_signal(signal.SIGTERM)
        with urllib.request.urlopen(f"http://127.0.0.1:{launched.port}", timeout=10) as response:  # noqa: S310
            assert response.status == 200 and "<!doctype html>" in response.read().decode().lower()
        workers = [pid for pid in children if "--worker-id" in Path(f"/proc/{pid}/cmdline").read_text()]
        assert len(workers) == 2
        with ViserClient(launched.port) as client:  # a websocket through nginx
            client.wait_for_label("Present", timeout=30.0)
        os.kill(workers[0], signal.SIGKILL)  # a worker dies: reported; the other goes on
        poll_until(lambda: "ended (exit -9)" in launched.stderr(), 10.0, 0.1)
        assert "1 worker(s) go on" in launched.stderr() and launched.process.poll() is None
        for _ in range(2):  # new browsers reach the worker that answers
            with ViserClient(launched.port) as client:
                client.wait_for_label("Present", timeout=30.0)
        launched.process.send_signal(signal.SIGINT)  # Ctrl-C
        assert launched.process.wait(30) == 0
        assert termed.process.wait(30) == 0
        poll_until(lambda: not any(_alive(pid) for pid in children | term_children), 10.0, 0.1)
    finally:
        launched.close()
        termed.close()


def test_nginx_spreads_websockets_by_least_connections_and_runs_without_root(tmp_path: Path) -> None:
    text = nginx_config(tmp_path, "0.0.0.0:8080", ["127.0.0.1:9001", "10.0.0.7:9001"])
    assert "least_conn;" in text and "ip_hash" not in text and "hash " not in text
    assert "server 127.0.0.1:9001;" in text and "server 10.0.0.7:9001;" in text
    assert "proxy_set_header Upgrade $http_upgrade;" in text and "Connection $connection_upgrade" in text
    assert "daemon off;" in text and "proxy_read_timeout 1d;" in text
    for line in text.splitlines():  # everything nginx writes is in the run's folder
        if line.strip().startswith(("pid ", "error_log ", "client_body_temp_path", "proxy_temp_path")):
            assert str(tmp_path) in line, line


@pytest.mark.parametrize("missing", ["nginx", "redis-server"])
def test_a_missing_program_is_named_with_its_install_command(missing: str, monkeypatch: pytest.MonkeyPatch,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    real_which = services.shutil.which
    monkeypatch.setattr(services.shutil, "which",
                        lambda program, *a, **k: None if program == missing else real_which(program, *a, **k))
    args = argparse.Namespace(workers=2, host="127.0.0.1", port=free_port(), presenter_code=None, redis=None,
                              projector=False)
    handler = signal.getsignal(signal.SIGINT)  # pytest's (ignored when the run itself was started in the background)
    started = time.monotonic()
    assert launch_main(args) == 2
    assert time.monotonic() - started < 5.0  # said at once, nothing started
    assert f"{missing} is not installed" in capsys.readouterr().err
    with pytest.raises(SystemExit) as stop:  # the command line says the same
        app_main(["--workers", "2", "--port", str(free_port())])
    assert stop.value.code == 2
    assert f"sudo apt-get install {missing}" in capsys.readouterr().err
    assert signal.getsignal(signal.SIGINT) is handler  # launch_main gave back the handler it found


@needs_parts
def test_a_port_in_use_is_said_before_anything_starts(capsys: pytest.CaptureFixture[str]) -> None:
    import socket

    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        args = argparse.Namespace(workers=2, host="127.0.0.1", port=port, presenter_code=None, redis=None,
                                  projector=False)
        started = time.monotonic()
        assert launch_main(args) == 1
        assert time.monotonic() - started < 5.0
    assert f"port {port} on 127.0.0.1 is in use" in capsys.readouterr().err
