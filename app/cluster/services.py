"""The real parts the app starts for `--workers` and its tests: redis-server and nginx as child
processes on free local ports (no systemd, no files outside a temporary folder)."""

from __future__ import annotations

import contextlib
import os
import shutil
import socket
import subprocess
import tempfile
import time

__all__ = ["INSTALL", "MissingProgram", "free_port", "require", "start_redis", "stop_process", "wait_for_port"]

REDIS_FOLDER_PREFIX = "rigid-body-lab-redis-"  # `start_redis`'s working folder (removed by `stop_process`)
INSTALL = {"redis-server": "sudo apt-get install redis-server", "nginx": "sudo apt-get install nginx"}


class MissingProgram(RuntimeError):
    """A program the app needs is not installed (the message says how to install it)."""


def require(program: str) -> str:
    """The path of `program` on PATH (or in /usr/sbin), else MissingProgram with the install command."""
    path = shutil.which(program) or shutil.which(program, path="/usr/sbin:/usr/bin:/usr/local/sbin")
    if path is None:
        raise MissingProgram(f"{program} is not installed; `--workers` needs it. Install it with: "
                             f"{INSTALL.get(program, program)}")
    return path


def free_port(host: str = "127.0.0.1") -> int:
    """A TCP port free on `host` now (the OS's choice)."""
    with socket.socket() as sock:
        sock.bind((host, 0))
        return int(sock.getsockname()[1])


def wait_for_port(port: int, host: str = "127.0.0.1", timeout: float = 10.0,
                  process: subprocess.Popen[bytes] | None = None) -> None:
    """Return once `host:port` accepts connections; RuntimeError after `timeout` [s] or if
    `process` ends first."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if process is not None and process.poll() is not None:
            raise RuntimeError(f"{process.args!r} ended (exit {process.returncode}) before listening on {port}")
        with contextlib.suppress(OSError), socket.create_connection((host, port), timeout=0.2):
            return
        time.sleep(0.05)
    raise RuntimeError(f"nothing listens on {host}:{port} after {timeout} s")


def start_redis(port: int | None = None, password: str | None = None, bind: str = "127.0.0.1",
                keep_in: str | os.PathLike[str] | None = None) -> tuple[str, subprocess.Popen[bytes]]:
    """Start redis-server on `bind:port` (a free port if None) and return (its URL, the process).
    In memory only (no dump file), or, with `keep_in` (a folder, made if missing and kept), with
    its append-only file there: what it holds (tasks, `app.tasks`) survives a restart.
    MissingProgram if redis-server is not installed."""
    program = require("redis-server")
    port = port or free_port(bind)
    if keep_in is not None:
        os.makedirs(keep_in, exist_ok=True)
        folder, appendonly = os.fspath(keep_in), "yes"
    else:
        folder, appendonly = tempfile.mkdtemp(prefix=REDIS_FOLDER_PREFIX), "no"
    args = [program, "--port", str(port), "--bind", bind, "--save", "", "--appendonly", appendonly,
            "--appendfsync", "everysec", "--dir", folder, "--loglevel", "warning"]
    if password:
        args += ["--requirepass", password]
    process = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    wait_for_port(port, bind, process=process)
    auth = f":{password}@" if password else ""
    return f"redis://{auth}{bind}:{port}/0", process


def stop_process(process: subprocess.Popen[bytes] | None, timeout: float = 5.0) -> None:
    """Terminate `process` and wait for it (kill after `timeout` [s]); None or ended: nothing.  A
    redis-server from `start_redis` leaves no folder behind."""
    if process is None:
        return
    if process.poll() is not None:
        _remove_redis_folder(process)
        return
    process.terminate()
    try:
        process.wait(timeout)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait(timeout)
    with contextlib.suppress(Exception):
        if process.stderr is not None:
            process.stderr.close()
    _remove_redis_folder(process)


def _remove_redis_folder(process: subprocess.Popen[bytes]) -> None:
    """The (empty) working folder `start_redis` made for `process`, once it ended."""
    args = [str(a) for a in process.args] if isinstance(process.args, list) else []
    if "--dir" in args and process.poll() is not None:
        folder = args[args.index("--dir") + 1]
        if os.path.basename(folder).startswith(REDIS_FOLDER_PREFIX):
            shutil.rmtree(folder, ignore_errors=True)

