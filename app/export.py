"""Recordings for lecture notes: a scene's motion as a `.viser` file or a standalone HTML page.

    python -m app export --scene "Heavy top" --preset Loop --seconds 10 --out loop.html
    python -m app export --scene "Free body" --preset Dzhanibekov --seconds 8 --out flip.viser

The motion is computed faster than real time: the scene's simulation and its view run in a
private viser server with no browser (nothing is served), drawing into the shared scene while
viser's scene serializer records every message, with a sleep of one frame between frames.
`.viser` plays in viser's client (`index.html?playbackPath=file.viser`); `.html` is viser's
client with the recording embedded (`as_html`), which plays from `file://` with no network.
The `Record` button of the panel does the same from the current state of a browser's scene.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import math
import sys
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

import viser

from app.kit.core.room import Room
from app.scenes import SCENES
from app.theme import configure_scene

__all__ = ["FPS", "MAX_SECONDS", "RecorderTarget", "export_main", "record"]

FPS = 30.0  # frames per second of a recording (half the app's: the file stays small)
MAX_SECONDS = 120.0


class RecorderTarget:
    """What a view draws into while recording (an `app.kit.core.target.DrawTarget`): the private
    server's scene and panel, which no browser sees, under `root_prefix`; no controls (nobody
    acts on a recording) and no camera."""

    def __init__(self, server: viser.ViserServer, root_prefix: str = "") -> None:
        self.root_prefix = root_prefix
        self.scene = server.scene
        self.gui = server.gui
        self.controls = None
        self.camera = None
        self.client_id = -1
        self._server = server

    @contextlib.contextmanager
    def atomic(self) -> Iterator[None]:
        with self._server.atomic():
            yield

    def add_notification(self, title: str, body: str, **kwargs: Any) -> None:
        return None


def record(room: Room, seconds: float, *, fmt: str = "html",
           progress: Callable[[float], None] | None = None, fork: bool = True) -> bytes:
    """The next `seconds` of `room`'s simulation (from its current state; with fork=True the
    room itself is not touched) as `.viser` bytes (fmt "viser") or a standalone HTML page.

    progress(fraction) is called as the frames are computed.  ValueError for a bad format or
    length.
    """
    if fmt not in ("html", "viser"):
        raise ValueError(f"format {fmt!r}: choose html or viser")
    if not (0.0 < seconds <= MAX_SECONDS) or not math.isfinite(seconds):
        raise ValueError(f"seconds = {seconds!r}: between 0 and {MAX_SECONDS:g}")
    with contextlib.redirect_stdout(io.StringIO()):  # viser prints its URL panel regardless
        server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        configure_scene(server, room.scene.view)
        copy = room.fork() if fork else room
        view = room.scene(RecorderTarget(server), copy, lambda _where, fn: fn, None)
        serializer = server.get_scene_serializer()
        copy.playing = True
        dt = 1.0 / FPS
        frames = max(1, round(seconds * FPS))
        for k in range(frames):
            copy.advance(dt)
            view.frame(dt)
            serializer.insert_sleep(dt)
            if progress is not None and k % 15 == 0:
                progress(k / frames)
        if progress is not None:
            progress(1.0)
        return serializer.as_html().encode("utf-8") if fmt == "html" else serializer.serialize()
    finally:
        with contextlib.redirect_stdout(io.StringIO()):
            server.stop()


def export_main(argv: Sequence[str]) -> int:
    """`python -m app export ...`; returns the exit status (2: a bad name or value, one line)."""
    parser = argparse.ArgumentParser(prog="python -m app export",
                                     description="Record a scene's motion as .html or .viser.")
    parser.add_argument("--scene", required=True, help=f"one of: {', '.join(SCENES)}")
    parser.add_argument("--preset", help="a preset of the scene (default: its first)")
    parser.add_argument("--seconds", type=float, default=10.0, help="simulated seconds (default %(default)s)")
    parser.add_argument("--out", type=Path, required=True, help="OUT.html or OUT.viser")
    args = parser.parse_args(argv)
    scene = SCENES.get(args.scene)
    if scene is None:
        print(f"export: no scene {args.scene!r}; the scenes are: {', '.join(SCENES)}", file=sys.stderr)
        return 2
    names = [p.name for p in scene.presets()]
    if args.preset is not None and args.preset not in names:
        print(f"export: {args.scene} has no preset {args.preset!r}; its presets are: {', '.join(names)}",
              file=sys.stderr)
        return 2
    suffix = args.out.suffix.lower()
    if suffix not in (".html", ".viser"):
        print(f"export: --out {args.out}: the file must end in .html or .viser", file=sys.stderr)
        return 2
    room = Room(scene, scene.new_simulation())
    if args.preset is not None:
        scene.apply_preset(room, args.preset)
    try:
        data = record(room, args.seconds, fmt=suffix[1:])
    except ValueError as error:
        print(f"export: {error}", file=sys.stderr)
        return 2
    args.out.write_bytes(data)
    print(f"{args.out}: {len(data) / 1e6:.2f} MB, {args.seconds:g} s of {args.scene}"
          + (f" ({args.preset})" if args.preset else ""))
    return 0
