"""`rigid-body-lab --workers N`: Redis, N app processes and nginx in front of them on one port.

    rigid-body-lab --workers 2 [--host H] [--port P] [--presenter-code C] [--projector] [--redis URL]

What it starts, each a child process it stops again (Ctrl-C, SIGTERM, or when it dies itself:
the children have PR_SET_PDEATHSIG on Linux):

- redis-server on a free local port, bound to 127.0.0.1, with a random password, its append-only
  file in the data folder's `redis/` (tasks and submissions survive a restart, `app.tasks`)
  (`app.cluster.services.start_redis`), unless `--redis URL` names one;
- N workers, `python -m app --host 127.0.0.1 --port Pk --worker-id wk [--projector]`, on free
  local ports; the Redis URL (with its password) and the one presenter code reach them in the
  environment (`app.main.REDIS_ENV`, `CODE_ENV`), not on the command line that `ps` shows; each
  worker's output goes to `wk.log` in the run's temporary folder;
- nginx (`nginx_config`) on `--host:--port`: one `upstream` with `least_conn` (never `ip_hash`:
  a lecture hall's Wi-Fi is one NAT address), the websocket upgrade headers, day-long read
  timeouts, `daemon off` and its pid, logs and temporary files in the run's folder (no root).
  viser serves the page, its assets and the websocket on one port and path: one `location /`.

The code is made once (`app.lecture.gate.new_code`, unless `--presenter-code`) and printed once.
A worker that ends is reported with the end of its log; the others go on (nginx sends new
browsers to those that answer).  nginx or Redis ending stops everything.  A missing nginx or
redis-server is said at start with the command that installs it.
"""

from __future__ import annotations

import argparse
import contextlib
import ctypes
import os
import re
import secrets
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from app.cluster.services import MissingProgram, free_port, require, start_redis, stop_process, wait_for_port
from app.i18n import DEFAULT_LANGUAGE, translator
from app.lecture.gate import new_code
from app.userdata import default_data_dir

__all__ = ["WORKER_START_S", "Launch", "check_port_free", "launch_main", "nginx_config", "start_nginx",
           "start_worker"]

WORKER_START_S = 90.0  # [s] a worker has this long to listen (imports and presets on a busy machine)
POLL_S = 0.5  # [s] the launcher looks at its children this often
REDIS_FOLDER = "redis"  # the app's own redis-server's append-only file, in the data folder
REDIS_ENV, CODE_ENV = "RBL_REDIS_URL", "RBL_PRESENTER_CODE"  # as `app.main` reads them
_WORKER_LINE = re.compile(r"worker (\S+) on http://[^\s:]+:(\d+)")


def nginx_config(folder: str | Path, listen: str, upstreams: Sequence[str], *, worker_processes: str = "auto",
                 extra_upstream: str = "") -> str:
    """nginx.conf for `listen` ("host:port") in front of `upstreams` ("host:port" each), everything
    it writes inside `folder`.  `extra_upstream`: lines added to each `server` (e.g. "max_fails=1
    fail_timeout=5s")."""
    folder = Path(folder)
    servers = "\n".join(f"        server {address} {extra_upstream}".rstrip() + ";" for address in upstreams)
    return f"""# rigid-body-lab --workers: generated; run as `nginx -p {folder} -c {folder}/nginx.conf`
daemon off;
worker_processes {worker_processes};
worker_rlimit_nofile 16384;
pid {folder}/nginx.pid;
error_log {folder}/nginx-error.log warn;
events {{ worker_connections 8192; }}
http {{
    access_log off;
    client_body_temp_path {folder}/client_body;
    proxy_temp_path {folder}/proxy;
    fastcgi_temp_path {folder}/fastcgi;
    uwsgi_temp_path {folder}/uwsgi;
    scgi_temp_path {folder}/scgi;
    map $http_upgrade $connection_upgrade {{ default upgrade; '' close; }}
    upstream rigid_body_lab {{
        least_conn;  # websockets by least connections, never by client address (one NAT address per hall)
        zone rigid_body_lab 64k;  # the counts shared by nginx's worker processes
{servers}
    }}
    server {{
        listen {listen};
        location / {{
            proxy_pass http://rigid_body_lab;
            proxy_http_version 1.1;
            proxy_set_header Upgrade $http_upgrade;
            proxy_set_header Connection $connection_upgrade;
            proxy_set_header Host $host;
            proxy_read_timeout 1d;
            proxy_send_timeout 1d;
            proxy_buffering off;
            proxy_connect_timeout 2s;
        }}
    }}
}}
"""


def check_port_free(host: str, port: int) -> None:
    """RuntimeError naming `host:port` if something listens there already (said before anything starts)."""
    with socket.socket() as sock:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # as nginx binds
        try:
            sock.bind((host, port))
        except OSError as error:
            raise RuntimeError(f"port {port} on {host or '*'} is in use ({error.strerror}); choose another with "
                               "--port") from None


def _die_with_parent() -> None:
    """In the child, before exec: SIGTERM when the launcher ends, however it ends (Linux)."""
    with contextlib.suppress(Exception):
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG


def _popen(args: list[str], **kwargs: Any) -> subprocess.Popen[bytes]:
    preexec = _die_with_parent if sys.platform.startswith("linux") else None
    return subprocess.Popen(args, start_new_session=True, preexec_fn=preexec, **kwargs)  # noqa: PLW1509


def start_nginx(listen_host: str, listen_port: int, upstreams: Sequence[str], folder: str | Path,
                timeout: float = 10.0, **config: Any) -> subprocess.Popen[bytes]:
    """nginx in front of `upstreams` on listen_host:listen_port (config and files in `folder`),
    once it listens.  MissingProgram if nginx is not installed; RuntimeError (with nginx's own
    words) if it cannot start, e.g. the port is taken."""
    program = require("nginx")
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "nginx.conf").write_text(nginx_config(folder, f"{listen_host}:{listen_port}", upstreams, **config))
    log = open(folder / "nginx-stderr.log", "wb")  # noqa: SIM115 - the child writes it
    process = _popen([program, "-p", str(folder), "-c", str(folder / "nginx.conf"), "-e",
                      str(folder / "nginx-error.log")], stdout=log, stderr=subprocess.STDOUT)
    log.close()
    try:
        wait_for_port(listen_port, "127.0.0.1" if listen_host in ("0.0.0.0", "") else listen_host,  # noqa: S104
                      timeout=timeout, process=process)
    except RuntimeError as error:
        stop_process(process)
        words = _tail(folder / "nginx-error.log") or _tail(folder / "nginx-stderr.log")
        raise RuntimeError(f"nginx did not start on {listen_host}:{listen_port}: {words or error}") from None
    return process


def start_worker(worker_id: str, port: int, folder: str | Path, redis_url: str, code: str, *,
                 host: str = "127.0.0.1", projector: bool = False,
                 data_dir: str | Path | None = None, language: str = "en") -> subprocess.Popen[bytes]:
    """One app worker (`python -m app ... --worker-id`), its output in folder/<worker_id>.log;
    `data_dir` the lecturer's data folder (every worker the same one); `language` a new browser's."""
    env = dict(os.environ, **{REDIS_ENV: redis_url, CODE_ENV: code, "PYTHONUNBUFFERED": "1"})
    args = [sys.executable, "-m", "app", "--host", host, "--port", str(port), "--worker-id", worker_id]
    if projector:
        args.append("--projector")
    if data_dir:
        args += ["--data-dir", str(data_dir)]
    if language != "en":
        args += ["--language", language]
    with open(Path(folder) / f"{worker_id}.log", "wb") as log:
        return _popen(args, env=env, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)


def _tail(path: Path, lines: int = 8) -> str:
    with contextlib.suppress(OSError):
        return "\n".join(path.read_text(errors="replace").strip().splitlines()[-lines:])
    return ""


def _worker_port(log: Path, process: subprocess.Popen[bytes], timeout: float) -> int:
    """The port the worker says it listens on (viser moves up if the one asked is taken)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        with contextlib.suppress(OSError):
            match = _WORKER_LINE.search(log.read_text(errors="replace"))
            if match:
                return int(match.group(2))
        if process.poll() is not None:
            raise RuntimeError(f"worker ended (exit {process.returncode}) before listening:\n{_tail(log)}")
        time.sleep(0.1)
    raise RuntimeError(f"a worker did not listen within {timeout:.0f} s:\n{_tail(log)}")


class Launch:
    """What `--workers` started: Redis (unless given), the workers, nginx; `stop` stops them all."""

    def __init__(self) -> None:
        self.folder = Path(tempfile.mkdtemp(prefix="rigid-body-lab-"))
        self.redis: subprocess.Popen[bytes] | None = None
        self.redis_url = ""
        self.workers: dict[str, subprocess.Popen[bytes]] = {}
        self.ports: dict[str, int] = {}
        self.nginx: subprocess.Popen[bytes] | None = None
        self.reported: set[str] = set()  # workers whose end was said

    def start(self, workers: int, host: str, port: int, code: str, redis_url: str | None = None,
              projector: bool = False, data_dir: str | Path | None = None, language: str = "en") -> None:
        require("nginx")
        check_port_free(host, port)
        if redis_url is None:
            require("redis-server")
            kept = Path(data_dir).expanduser() if data_dir else default_data_dir()  # tasks survive a restart
            self.redis_url, self.redis = start_redis(password=secrets.token_urlsafe(24), keep_in=kept / REDIS_FOLDER)
        else:
            self.redis_url = redis_url
        for k in range(1, workers + 1):
            worker_id = f"w{k}"
            self.workers[worker_id] = start_worker(worker_id, free_port(), self.folder, self.redis_url, code,
                                                   projector=projector, data_dir=data_dir, language=language)
        for worker_id, process in self.workers.items():
            self.ports[worker_id] = _worker_port(self.folder / f"{worker_id}.log", process, WORKER_START_S)
            wait_for_port(self.ports[worker_id], process=process, timeout=WORKER_START_S)
        self.nginx = start_nginx(host, port, [f"127.0.0.1:{p}" for p in self.ports.values()], self.folder)

    def check(self) -> str | None:
        """Say what ended since the last look; the reason to stop everything, or None."""
        if self.nginx is not None and self.nginx.poll() is not None:
            return f"nginx ended (exit {self.nginx.returncode}): {_tail(self.folder / 'nginx-error.log')}"
        if self.redis is not None and self.redis.poll() is not None:
            return f"redis-server ended (exit {self.redis.returncode})"
        for worker_id, process in self.workers.items():
            if process.poll() is not None and worker_id not in self.reported:
                self.reported.add(worker_id)
                left = sum(1 for p in self.workers.values() if p.poll() is None)
                print(f"rigid-body-lab: worker {worker_id} (pid {process.pid}) ended (exit {process.returncode}); "
                      f"its browsers lost their rooms; {left} worker(s) go on.  The end of its log:\n"
                      f"{_tail(self.folder / f'{worker_id}.log')}", file=sys.stderr, flush=True)
        if self.workers and all(p.poll() is not None for p in self.workers.values()):
            return "every worker ended"
        return None

    def pids(self) -> list[int]:
        """The pids of every child started (tests check that none is left)."""
        return [p.pid for p in (self.nginx, *self.workers.values(), self.redis) if p is not None]

    def stop(self) -> None:
        """nginx first (no new browsers), then the workers (each frees its lock), then Redis."""
        stop_process(self.nginx)
        for process in self.workers.values():
            if process.poll() is None:
                process.send_signal(signal.SIGTERM)
        for process in self.workers.values():
            stop_process(process)
        stop_process(self.redis)
        if self.reported:
            print(f"rigid-body-lab: the workers' logs stay in {self.folder}", file=sys.stderr)
        else:
            shutil.rmtree(self.folder, ignore_errors=True)


def _interrupt(_signum: int, _frame: Any) -> None:
    raise KeyboardInterrupt


def launch_main(args: argparse.Namespace) -> int:
    """`--workers N` (the options of `app.main._parse_args`): start, serve until Ctrl-C or
    SIGTERM, stop everything; the exit status."""
    code = args.presenter_code or new_code()
    tr = translator(getattr(args, "language", DEFAULT_LANGUAGE))  # the command line's language (app.cli_words)
    _ = tr.gettext
    launch = Launch()
    handlers = {sig: signal.signal(sig, _interrupt)  # SIGINT also when started with it ignored (in the background)
                for sig in (signal.SIGTERM, signal.SIGINT)}
    try:
        try:
            launch.start(args.workers, args.host, args.port, code, redis_url=args.redis, projector=args.projector,
                         data_dir=getattr(args, "data_dir", None), language=getattr(args, "language", "en"))
        except MissingProgram as error:
            print(f"rigid-body-lab: {error}", file=sys.stderr, flush=True)
            return 2
        except RuntimeError as error:
            print("rigid-body-lab: " + _("could not start: {reason}").format(reason=error), file=sys.stderr,
                  flush=True)
            return 1
        opened = _("open {url} in a browser; presenter code: {code}").format(url=f"http://{args.host}:{args.port}",
                                                                            code=code)
        behind = tr.ngettext("({n} worker behind nginx, pid {pid})", "({n} workers behind nginx, pid {pid})",
                             args.workers).format(n=args.workers, pid=os.getpid())
        print(f"{opened}  {behind}", flush=True)
        while True:
            reason = launch.check()
            if reason is not None:
                print("rigid-body-lab: " + _("{reason}; stopping").format(reason=reason), file=sys.stderr, flush=True)
                return 1
            time.sleep(POLL_S)
    except KeyboardInterrupt:
        return 0
    finally:
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # a second Ctrl-C does not cut the stopping short
        try:
            launch.stop()
        finally:
            for sig, handler in handlers.items():
                signal.signal(sig, handler)
