"""The `For the notes` folder of one browser's panel: recordings and screenshots for lecture notes.

This module owns `Notes`: the folder, `Record` (the next seconds of the scene shown, computed
from a copy of its room faster than real time, offered as .html and .viser downloads) and
`Screenshot` (a PNG of the browser's 3D view: the scene without the panel and without the drag
gizmos, which are hidden while the browser renders it).  The browser saves both at once under
their whole names (`app.kit.panel.download.save_download`: no toast with a link to click).
Both work in a thread and report their errors in the browser's panel.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

import imageio.v3 as iio
import viser

from app.export import MAX_SECONDS, record
from app.i18n import N_, Labels, Translator, for_gui
from app.kit.core.common import Wrap, checked_value
from app.kit.core.room import Room
from app.kit.panel.download import save_download

__all__ = ["Notes"]


class Notes:
    """The `For the notes` folder and what its buttons make.

    Args:
        client: the browser.
        guard: its session's guard: the buttons' callbacks run in it.
        report_error: shows an error in the browser's panel (the threads' errors go there).
        room: the room the browser shows now.
        view: the view drawing it in this browser (its `hide_gizmos(hidden)` takes the drag
            gizmos out of a screenshot), or something without that method (a follower's panel).

    Attributes:
        folder: the folder.  last_recording: (.html, .viser) last offered, or None;
        last_screenshot: the PNG last offered, or None.
    """

    def __init__(self, client: viser.ClientHandle, guard: Wrap,
                 report_error: Callable[[str, BaseException], None], room: Callable[[], Room],
                 view: Callable[[], Any] = lambda: None) -> None:
        self.client = client
        self._guard = guard
        self._view = view
        self._report_error = report_error
        self._room = room
        self.last_recording: tuple[bytes, bytes] | None = None
        self.last_screenshot: bytes | None = None
        gui = client.gui
        self.folder = gui.add_folder(N_("For the notes"), expand_by_default=False)
        with self.folder:
            self.gui_record_seconds = gui.add_number(N_("Record [s]"), 10.0, min=1.0, max=60.0, step=1.0,
                                                     hint=N_("simulated seconds from now, computed faster than "
                                                             "real time"))
            self.gui_record = gui.add_button(N_("Record"), icon=viser.Icon.VIDEO,
                                             hint=N_("download the motion as .html (plays offline) and .viser"))
            self.gui_record_progress = gui.add_progress_bar(0.0, visible=False)
            self.gui_screenshot = gui.add_button(N_("Screenshot"), icon=viser.Icon.CAMERA,
                                                 hint=N_("download a PNG of this view, for slides"))
        self.words = Labels(gui)
        self.words.take(self.folder, self.gui_record_seconds, self.gui_record, self.gui_screenshot)
        self.gui_record.on_click(guard("record", lambda _event: self.record(self.gui_record_seconds.value)))
        self.gui_screenshot.on_click(guard("screenshot", lambda _event: self.screenshot()))

    def relabel(self, tr: Translator) -> None:
        """The folder's words in `tr`'s language (the browser chose another)."""
        self.words.relabel(tr)

    def _file_title(self, room: Room) -> str:
        """The scene's title in a download's name, in the browser's language ("euler_angles", "euler-winkel")."""
        return for_gui(self.client.gui).gettext(room.scene.title).lower().replace(" ", "_")

    def record(self, seconds: Any, *, wait: bool = False) -> threading.Thread:
        """Record the next `seconds` of the scene shown, from its current state, and offer it as
        .html and .viser downloads.  The copy is taken now (`Room.fork`; the room shown is not
        touched); the frames are computed in a thread.  ValueError for a value out of range."""
        value = checked_value(seconds, 1.0, MAX_SECONDS)
        if value is None:
            raise ValueError(for_gui(self.client.gui).gettext("Record: {seconds} s refused: between 1 and {most} s")
                             .format(seconds=repr(seconds), most=f"{MAX_SECONDS:g}"))
        room = self._room()
        copy = room.fork()
        title = self._file_title(room)
        bar = self.gui_record_progress

        def work() -> None:
            try:
                bar.visible = True
                html = record(copy, value, fmt="html", progress=lambda f: setattr(bar, "value", 50.0 * f))
                data = record(copy, value, fmt="viser", progress=lambda f: setattr(bar, "value", 50.0 + 50.0 * f))
                save_download(self.client, f"{title}_{value:g}s.html", html)
                save_download(self.client, f"{title}_{value:g}s.viser", data)
                self.last_recording = (html, data)
            except Exception as error:  # noqa: BLE001 - shown, never raised into a thread
                self._report_error("record", error)
            finally:
                bar.visible = False

        thread = threading.Thread(target=work, name=f"record-{self.client.client_id}", daemon=True)
        thread.start()
        if wait:
            thread.join()
        return thread

    def screenshot(self, *, wait: bool = False) -> threading.Thread:
        """Ask this browser for a render of its 3D view, the drag gizmos hidden meanwhile, and
        save it as `<scene>_t<time>s.png` (in a thread: the browser answers in a second or so)."""
        room = self._room()
        name = f"{self._file_title(room)}_t{room.shown_t:.1f}s.png"
        view = self._view()
        hide = getattr(view, "hide_gizmos", None)

        def work() -> None:
            try:
                if hide is not None:
                    self._guard("screenshot", hide)(True)
                try:
                    image = self.client.get_render(height=720, width=1280, transport_format="png")
                finally:
                    if hide is not None:
                        self._guard("screenshot", hide)(False)
                png = iio.imwrite("<bytes>", image, extension=".png")
                save_download(self.client, name, png)
                self.last_screenshot = png
            except Exception as error:  # noqa: BLE001
                self._report_error("screenshot", error)

        thread = threading.Thread(target=work, name=f"screenshot-{self.client.client_id}", daemon=True)
        thread.start()
        if wait:
            thread.join()
        return thread
