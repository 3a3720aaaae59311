"""The scenes in a Jupyter notebook: live while the kernel runs, a recorded player in the rendered page.

    from app import notebook
    notebook.show("Heavy top", preset="Loop")            # the cell's output: the scene

`show` starts the app for this one scene in the kernel (a viser server on a free loopback port,
its 60 Hz loop in a thread: the same app as `python -m app`, every browser that opens it getting
the scene and preset with its panel) and records the next `seconds` of the same motion as viser's
standalone player (`app.export.record`, ~0.85 MB for 5 s).  The cell's output is one HTML block:

- an `<iframe>` whose `srcdoc` is the recorded player, which plays from the notebook file alone
  (viser's client and the recording are in it; no script or style comes from the network), and
- a short script that asks the live server for its page and, if it answers, points the frame at
  it.  In Jupyter with the kernel running the cell shows the live scene; in the notebook
  rendered without a kernel (`jupyter nbconvert --to html`, Jupyter Book, a page served over
  https, or a viewer that runs no scripts) the server does not answer and the player stays.

The live scene is served at `SceneDisplay.url` (http://127.0.0.1:PORT) to this machine only;
`SceneDisplay.stop()` (or `stop_all()`, also run when the kernel exits) ends it.  The notebook
packages are the optional extra `notebook` (`pip install -e ".[notebook]"`); this module
imports none of them: a plain Python session gets the same object (its `url` and `player_html`).
"""

from __future__ import annotations

import atexit
import contextlib
import html
import io
import itertools
import json
import threading
from collections.abc import Iterator
from dataclasses import dataclass, field

import rich
import viser

from app.export import record
from app.kit.core.room import Room
from app.main import App
from app.scenes import SCENES
from app.session import Session
from app.theme import configure_scene

__all__ = ["PLAYER_MARK", "SceneDisplay", "show", "stop_all"]

PLAYER_MARK = "__VISER_EMBED_DATA__"  # in every recorded player: its recording (viser's as_html)
DEFAULT_SECONDS = 5.0  # [s] recorded for the player
DEFAULT_HEIGHT = 520  # [px] of the frame in the notebook

_numbers = itertools.count(1)
_live: list[App] = []
_live_lock = threading.Lock()


@dataclass
class SceneDisplay:
    """One scene shown in a notebook: the live app (None with live=False) and the recorded player.

    scene, preset: what is shown; url: the live app's address ("" without one); player_html: the
    standalone player (a complete HTML document); height: of the frame [px].
    """

    scene: str
    preset: str | None
    player_html: str
    height: int = DEFAULT_HEIGHT
    app: App | None = None
    url: str = ""
    frame_id: str = field(default_factory=lambda: f"rigid-body-lab-{next(_numbers)}")

    def _repr_html_(self) -> str:
        """The cell's output: the player in a frame, switched to the live app when it answers."""
        caption = self.scene + (f" · {self.preset}" if self.preset else "")
        frame = (f'<iframe id="{self.frame_id}" class="rigid-body-lab-player" title="{html.escape(caption)}" '
                 f'srcdoc="{html.escape(self.player_html, quote=True)}" width="100%" height="{self.height}" '
                 'style="border:1px solid #ddd;display:block" allow="fullscreen"></iframe>')
        if not self.url:
            return frame
        element, url = json.dumps(self.frame_id), json.dumps(self.url)
        probe = (f"<script>(function(){{var f=document.getElementById({element}),u={url};"
                 "if(!f||!window.fetch)return;"
                 "fetch(u,{mode:'no-cors',cache:'no-store'}).then(function(){f.removeAttribute('srcdoc');f.src=u;})"
                 ".catch(function(){});})();</script>")
        return frame + probe

    def __repr__(self) -> str:
        return (f"SceneDisplay({self.scene!r}, preset={self.preset!r}, url={self.url or None!r}, "
                f"player={len(self.player_html) / 1e6:.2f} MB)")

    def stop(self) -> None:
        """Stop the live app (the player in the output stays); idempotent."""
        if self.app is not None:
            with _quiet():
                self.app.stop()
            with _live_lock:
                if self.app in _live:
                    _live.remove(self.app)


@contextlib.contextmanager
def _quiet() -> Iterator[None]:
    """viser's start and stop panels kept out of the cell's output (in Jupyter, rich writes them
    as display outputs, not to stdout)."""
    console = rich.get_console()
    before = console.quiet
    console.quiet = True
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            yield
    finally:
        console.quiet = before


def _live_app(scene: str, preset: str | None, port: int) -> App:
    """The app on 127.0.0.1:port (0: a free one), each browser's session opening `scene` at `preset`."""
    with _quiet():  # viser prints its URL panel regardless
        server = viser.ViserServer(host="127.0.0.1", port=port, verbose=False)
    configure_scene(server, SCENES[scene].view)
    app: App

    def open_scene(client: viser.ClientHandle) -> Session:
        session = Session(client, scene, lectern=app.lectern)
        if preset is not None:
            session.apply_preset(preset)
        return session

    app = App(server, session_factory=open_scene).start()
    with _live_lock:
        _live.append(app)
    return app


def show(scene: str, preset: str | None = None, *, seconds: float = DEFAULT_SECONDS,
         height: int = DEFAULT_HEIGHT, live: bool = True, port: int = 0) -> SceneDisplay:
    """`scene` (a title of the Scene dropdown) at `preset` (one of its presets; None: its first) in
    a notebook: live while the kernel runs (live=True), and the next `seconds` [s] recorded as the
    player the rendered notebook plays.  port: the live app's (0: a free one).

    ValueError naming the scenes or the scene's presets for a name it does not have.
    """
    if scene not in SCENES:
        raise ValueError(f"no scene {scene!r}; the scenes are: {', '.join(SCENES)}")
    spec = SCENES[scene]
    names = [p.name for p in spec.presets()]
    if preset is not None and preset not in names:
        raise ValueError(f"{scene} has no preset {preset!r}; its presets are: {', '.join(names)}")
    room = Room(spec, spec.new_simulation())
    if preset is not None:
        spec.apply_preset(room, preset)
    with _quiet():
        player = record(room, seconds, fmt="html", fork=False).decode("utf-8")
    shown = SceneDisplay(scene=scene, preset=preset, player_html=player, height=height)
    if live:
        shown.app = _live_app(scene, preset, port)
        shown.url = f"http://127.0.0.1:{shown.app.port}/"
    return shown


def stop_all() -> None:
    """Stop every live app this kernel started (run at exit)."""
    with _live_lock:
        apps = list(_live)
        _live.clear()
    for app in apps:
        with contextlib.suppress(Exception), _quiet():
            app.stop()


atexit.register(stop_all)
