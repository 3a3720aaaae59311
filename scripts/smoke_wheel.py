"""Smoke test of the package as a user installs it: build the wheel, install it, run it elsewhere.

    python3 scripts/smoke_wheel.py            # in .ci/run; exits 1 with a message on any failure
    python3 scripts/smoke_wheel.py --keep     # leave the temp folder (venv, wheel, flip.html)

Steps (each timed):
1. copy what the wheel is built from (pyproject.toml, README.md, app/, physics/, assets/) to a
   temp folder and build the wheel there with a fresh venv's pip (the checkout gets no build/);
2. install the wheel into that fresh venv (dependencies from the package index);
3. from an empty folder outside the checkout: check that `app` and its data (`app.data`) are
   the installed ones, run `python -m physics methods`;
4. start `rigid-body-lab --port <free port>`, wait until GET / answers 200, connect a pure-Python
   websocket client (below, run by the installed venv's Python in isolated mode, so it cannot
   import the checkout), select the "Free body" scene, press Play, and see the body's
   orientation arrive, changing; stop the server with Ctrl-C (SIGINT) and check it exits cleanly;
   then the same start, GET / and stop with `python -m app --port <free port>`;
5. `python -m app export --scene "Free body" --preset Dzhanibekov --seconds 2 --out flip.html`
   there, and check the file.

Needs only the standard library (any Python >= 3.11 with `venv`); the client part (`--client
PORT`) needs websockets, msgspec and zstandard, which viser installs.  The client speaks viser's
websocket protocol as `benchmarks/ws_client.py` does (docs/VISER.md §3), in a few lines.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGED = ("pyproject.toml", "setup.py", "README.md", "app", "physics", "assets")  # what the wheel is built from
SCENE = "Free body"  # the scene the client selects and plays (and the export records)
SCENE_LABEL, PLAY_LABEL, PAUSE_LABEL = "Scene", "Play", "Pause"  # app.session, app.kit.panel.gui
EXPORT_ARGS = ("export", "--scene", SCENE, "--preset", "Dzhanibekov", "--seconds", "2", "--out", "flip.html")
MIN_EXPORT_BYTES = 100_000  # an export holds viser's client (~0.8 MB); an error page is far smaller
PLAY_SECONDS = 2.0  # [s] the client watches the playing scene this long
MIN_ORIENTATIONS = 20  # orientation messages of the body wanted in PLAY_SECONDS (60 Hz gives ~120)
START_TIMEOUT = 90.0  # [s] server start until GET / answers (a cold import of scipy/viser on a busy CI)
STEP_TIMEOUT = 30.0  # [s] each client wait (GUI element, label change)
INSTALL_TIMEOUT = 900.0  # [s] wheel build / pip install (downloads from the index)


class SmokeError(RuntimeError):
    """A failed step; the message says which and why."""


# --------------------------------------------------------------------------- orchestration
def run(cmd: list[str], cwd: Path, what: str, timeout: float = INSTALL_TIMEOUT) -> str:
    """Run `cmd` in `cwd` with a clean environment; its stdout; SmokeError with its output if it fails."""
    try:
        done = subprocess.run(cmd, cwd=cwd, env=clean_env(), capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        raise SmokeError(f"{what}: no answer within {timeout:g} s ({' '.join(cmd)})") from None
    if done.returncode != 0:
        raise SmokeError(f"{what}: exit code {done.returncode} ({' '.join(cmd)})\n{done.stdout[-3000:]}"
                         f"{done.stderr[-3000:]}")
    return done.stdout


def clean_env() -> dict[str, str]:
    """This process's environment without what would lead Python to the checkout or a venv."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV")}
    env["PYTHONUNBUFFERED"] = "1"
    return env


def copy_sources(dest: Path) -> Path:
    """The files the wheel is built from, copied to dest/src (no __pycache__, no build/, no .mo: the
    build compiles the catalogs, setup.py)."""
    src = dest / "src"
    src.mkdir(parents=True)
    for name in PACKAGED:
        path = ROOT / name
        if path.is_dir():
            shutil.copytree(path, src / name, ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "*.mo"))
        else:
            shutil.copy2(path, src / name)
    return src


def build_wheel(python: Path, dest: Path) -> Path:
    """Build the wheel from a copy of the sources with `python -m pip wheel`; its path (in dest/dist)."""
    src = copy_sources(dest)
    dist = dest / "dist"
    run([str(python), "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(dist), str(src)], dest, "build the wheel")
    wheels = sorted(dist.glob("*.whl"))
    if len(wheels) != 1:
        raise SmokeError(f"build the wheel: expected one wheel in {dist}, found {[w.name for w in wheels]}")
    return wheels[0]


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def serve(command: list[str], venv: Path, work: Path, play: bool) -> str:
    """Start the installed app with `command` (+ --port), check GET / (and, if `play`, a client
    playing a scene), stop it with Ctrl-C; what was seen."""
    port = free_port()
    server = subprocess.Popen([*command, "--port", str(port)], cwd=work, env=clean_env(),
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                              preexec_fn=_default_sigint)
    output: list[str] = []
    reader = threading.Thread(target=lambda: output.extend(iter(server.stdout.readline, "")), daemon=True)  # type: ignore[union-attr]
    reader.start()
    try:
        port = wait_until_serving(server, output, port)
        seen = f"GET / 200 on port {port}"
        if play:
            seen = run([str(venv / "bin" / "python"), "-I", str(Path(__file__).resolve()), "--client", str(port)],
                       work, "websocket client", timeout=4 * STEP_TIMEOUT)
    finally:
        if server.poll() is None:
            server.send_signal(signal.SIGINT)  # what Ctrl-C does: the app stops its server and exits
            try:
                server.wait(timeout=15)
            except subprocess.TimeoutExpired:
                server.kill()
                server.wait()
                raise SmokeError("server: still running 15 s after Ctrl-C (SIGINT); killed") from None
        reader.join(timeout=5)
    log = "".join(output)
    if server.returncode != 0 or "Traceback" in log:
        raise SmokeError(f"server: exit code {server.returncode} after Ctrl-C, output:\n{log[-3000:]}")
    return seen.strip()


def _default_sigint() -> None:
    """In the server's process: Ctrl-C (SIGINT) acts, even when this script was started with it
    ignored (`cmd &` in a non-interactive shell), so that Python turns it into KeyboardInterrupt."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def wait_until_serving(server: subprocess.Popen[str], output: list[str], port: int) -> int:
    """The port the server answers GET / with 200 on (viser moves to the next port if one is busy)."""
    deadline = time.monotonic() + START_TIMEOUT
    while time.monotonic() < deadline:
        if server.poll() is not None:
            time.sleep(0.2)  # let the reader take the last lines
            log = "".join(output)[-3000:]
            raise SmokeError(f"server: exited with code {server.returncode} before answering:\n{log}")
        said = re.search(r"open http://[\d.]+:(\d+)", "".join(output))
        if said:
            port = int(said.group(1))
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=5) as answer:
                    if answer.status == 200 and b"<html" in answer.read(4096).lower():
                        return port
            except OSError:
                pass
        time.sleep(0.25)
    raise SmokeError(f"server: GET / did not answer 200 within {START_TIMEOUT:g} s:\n{''.join(output)[-3000:]}")


def smoke(keep: bool) -> int:
    temp = Path(tempfile.mkdtemp(prefix="rbl-smoke-"))
    venv, work = temp / "venv", temp / "work"
    work.mkdir()
    started = time.monotonic()

    def step(text: str) -> None:
        print(f"[{time.monotonic() - started:6.1f} s] {text}", flush=True)

    try:
        step(f"fresh venv in {venv}")
        run([sys.executable, "-m", "venv", str(venv)], temp, "make the venv")
        python = venv / "bin" / "python"
        wheel = build_wheel(python, temp)
        step(f"built {wheel.name} ({wheel.stat().st_size / 1e3:.0f} kB)")
        run([str(python), "-m", "pip", "install", "-q", str(wheel)], temp, "install the wheel")
        step("installed it (dependencies from the index)")
        where = run([str(python), "-c", "import app, app.data; print(app.__file__); print(app.data.assets_root())"],
                    work, "import the installed app").split()
        site = str(venv)
        if len(where) != 2 or not all(w.startswith(site) for w in where):
            raise SmokeError(f"the app or its data is not the installed one: {where} (wanted under {site})")
        step(f"app and its data from {Path(where[1]).relative_to(venv)}")
        methods = run([str(python), "-m", "physics", "methods"], work, "python -m physics methods")
        if not methods.strip():
            raise SmokeError("python -m physics methods: printed nothing")
        step(f"python -m physics methods: {len(methods.splitlines())} lines")
        step(f"rigid-body-lab: {serve([str(venv / 'bin' / 'rigid-body-lab')], venv, work, play=True)}")
        step(f"python -m app: {serve([str(python), '-m', 'app'], venv, work, play=False)}")
        run([str(python), "-m", "app", *EXPORT_ARGS], work, "python -m app export")
        flip = work / "flip.html"
        size = flip.stat().st_size if flip.is_file() else 0
        if size < MIN_EXPORT_BYTES or b"<html" not in flip.read_bytes()[:4096].lower():
            raise SmokeError(f"python -m app export: {flip} is missing or not an HTML page of "
                             f"≥ {MIN_EXPORT_BYTES} B ({size} B)")
        step(f"python -m app export wrote {flip.name} ({flip.stat().st_size / 1e6:.2f} MB) in the empty folder")
    except SmokeError as error:
        print(f"smoke_wheel: FAILED: {error}", file=sys.stderr, flush=True)
        return 1
    finally:
        if keep:
            print(f"kept {temp}")
        else:
            shutil.rmtree(temp, ignore_errors=True)
    step("smoke test of the wheel passed")
    return 0


# --------------------------------------------------------------------------- the websocket client
def client_main(port: int) -> int:
    """Select SCENE, press Play, see the body's orientation stream in (run by the installed venv)."""
    if any(name == "app" or name.startswith(("app.", "physics")) for name in sys.modules):
        raise SmokeError("client: the app was imported into the client; it must only talk to the server")
    import math

    import msgspec.msgpack
    import viser
    import zstandard
    from viser import _messages
    from websockets.sync.client import connect
    from websockets.typing import Subprotocol

    lock = threading.Condition()
    gui: dict[str, dict] = {}  # uuid -> {"type", "label", "seq"}, every element created and not removed
    orientations: dict[str, list[tuple[float, ...]]] = {}  # node name -> wxyz received (since the last clear)
    counter = [0]

    def decode(frame: bytes) -> list[dict]:  # [u64 msgpack len][u64 zstd len][zstd msgpack][buffers]
        inner_len, comp_len = int.from_bytes(frame[:8], "little"), int.from_bytes(frame[8:16], "little")
        inner = zstandard.ZstdDecompressor().decompress(frame[16:16 + comp_len], max_output_size=inner_len)
        return list(msgspec.msgpack.decode(inner)["messages"])

    def drain() -> None:
        try:
            for frame in ws:
                messages = decode(frame if isinstance(frame, bytes) else frame.encode())
                with lock:
                    for message in messages:
                        kind = message.get("type", "")
                        if kind == "SetOrientationMessage":
                            orientations.setdefault(message["name"], []).append(tuple(message["wxyz"]))
                        elif kind.startswith("Gui") and isinstance(message.get("props"), dict) and "uuid" in message:
                            counter[0] += 1
                            gui[message["uuid"]] = {"type": kind, "label": str(message["props"].get("label", "")),
                                                    "value": message.get("value"), "seq": counter[0]}
                        elif kind == "GuiUpdateMessage" and message.get("uuid") in gui:
                            updates = message.get("updates", {})
                            if "label" in updates:
                                gui[message["uuid"]]["label"] = str(updates["label"])
                        elif kind == "GuiRemoveMessage":
                            gui.pop(message.get("uuid", ""), None)
                    lock.notify_all()
        except Exception:  # noqa: BLE001 - the connection closed
            pass

    def wait(what: str, predicate):  # the predicate's value, under the lock
        deadline = time.monotonic() + STEP_TIMEOUT
        with lock:
            while not (value := predicate()):
                if time.monotonic() > deadline:
                    raise SmokeError(f"client: {what} within {STEP_TIMEOUT:g} s; GUI labels: "
                                     f"{sorted({e['label'] for e in gui.values()})}")
                lock.wait(0.1)
            return value

    def find(label: str, kind: str, after: int = 0) -> str | None:
        found = [(e["seq"], uuid) for uuid, e in gui.items() if e["label"] == label and kind in e["type"]
                 and e["seq"] > after]
        return max(found)[1] if found else None

    def send(message) -> None:
        ws.send(msgspec.msgpack.encode(message.as_serializable_dict()))

    ws = connect(f"ws://127.0.0.1:{port}", subprotocols=[Subprotocol(f"viser-v{viser.__version__}")], max_size=None,
                 open_timeout=STEP_TIMEOUT)
    threading.Thread(target=drain, daemon=True).start()
    try:
        send(_messages.ViewerCameraMessage(  # a browser's first message: until then no session
            wxyz=(1.0, 0.0, 0.0, 0.0), position=(3.0, 3.0, 3.0), fov=math.radians(50.0), near=0.01, far=100.0,
            image_height=600, image_width=800, look_at=(0.0, 0.0, 0.0), up_direction=(0.0, 0.0, 1.0)))
        scene = wait(f"no {SCENE_LABEL!r} dropdown", lambda: find(SCENE_LABEL, "Dropdown"))
        wait("no Play button", lambda: find(PLAY_LABEL, "Button"))
        with lock:
            already = gui[scene]["value"] == SCENE
            mark = 0 if already else counter[0]
        send(_messages.GuiUpdateMessage(scene, {"value": SCENE}))
        play = wait(f"no Play button of {SCENE}", lambda: find(PLAY_LABEL, "Button", after=mark))
        time.sleep(0.5)  # the new panel is complete; nothing plays yet
        with lock:
            orientations.clear()
        send(_messages.GuiUpdateMessage(play, {"value": True}))  # a click
        wait("Play did not turn into Pause", lambda: gui.get(play, {}).get("label") == PAUSE_LABEL)
        time.sleep(PLAY_SECONDS)
        with lock:
            node, poses = max(orientations.items(), key=lambda item: len(item[1]), default=("", []))
        moved = len(set(poses))
        if len(poses) < MIN_ORIENTATIONS or moved < MIN_ORIENTATIONS // 2:
            raise SmokeError(f"client: {len(poses)} orientations ({moved} distinct) of the busiest node {node!r} "
                             f"in {PLAY_SECONDS:g} s of play, wanted ≥ {MIN_ORIENTATIONS}")
        print(f"GET / 200 on port {port}, {SCENE} playing: {len(poses)} orientations of {node} "
              f"in {PLAY_SECONDS:g} s ({moved} distinct)")
    finally:
        ws.close()
    return 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument("--keep", action="store_true", help="keep the temp folder (venv, wheel, flip.html)")
    parser.add_argument("--client", type=int, metavar="PORT", help=argparse.SUPPRESS)  # step 4's client
    args = parser.parse_args()
    if args.client is not None:
        try:
            return client_main(args.client)
        except SmokeError as error:
            print(error, file=sys.stderr)
            return 1
    return smoke(args.keep)


if __name__ == "__main__":
    raise SystemExit(main())
