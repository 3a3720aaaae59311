"""The projector layout of one browser: the `Projector` checkbox and what it changes.

This module owns the layout (`ProjectorLayout`): panel text >= 18 px (PROJECTOR_CSS), the
lesson's caption at PROJECTOR_CAPTION_PX (`app.lecture.caption`), a narrow panel docked on the
right, 3D labels PROJECTOR_LABEL_SCALE times larger, and the scene's camera view moved for the
narrow panel (`projector_view`); off, a narrow screen's camera centres the body above its bottom
sheet (`app.kit.draw.screen.narrow_view`).  A follower's browser takes the panel part only: the shared
scene's labels and camera are not its own.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import viser

from app.i18n import N_, Translator, for_gui
from app.kit.core.common import CameraView, Wrap, apply_camera
from app.kit.draw.screen import narrow_size, narrow_view
from app.lecture.caption import CAPTION_PROJECTOR_RULES
from app.viser_internals import scene_nodes

__all__ = ["BRAND_COLOR", "PROJECTOR_CSS", "PROJECTOR_LABEL_SCALE", "ProjectorLayout", "projector_view"]

BRAND_COLOR = (200, 110, 0)
PROJECTOR_LABEL_SCALE = 1.4
PROJECTOR_CSS = f"""<style>
html {{ font-size: 20px; }}
label, button, input, .mantine-Text-root, .mantine-Button-label, .mantine-InputWrapper-label,
.mantine-NumberInput-input, .mantine-Select-input, .mantine-TextInput-input, p, li, td {{ font-size: 19px !important; }}
code, pre {{ font-size: 15px !important; }}
pre {{ white-space: pre-wrap !important; overflow-wrap: anywhere; }}  /* wrapped in the narrow panel, never cut */
.mantine-Slider-markLabel {{ display: none; }}
.mantine-Flex-root:has(> div > p > label) {{ flex-wrap: wrap; }}
.mantine-Flex-root > div:has(> p > label) {{ width: 100% !important; }}
h3 {{ font-size: 22px !important; }}
{CAPTION_PROJECTOR_RULES}
</style>"""

PROJECTOR_WORDS = (N_("Projector"), N_("large text, a narrow panel, large 3D labels"))
"""The checkbox's label and hint (translated: `app.i18n`)."""


def projector_view(view: CameraView) -> CameraView:
    """A scene's camera view for the projector layout: the panel is a narrow side bar there, so
    the view looks nearer the origin (scenes frame their body left of centre, for the floating
    panel) and from 10 % farther."""
    look_at = tuple(0.3 * c for c in view.look_at)
    position = tuple(a + 1.1 * (p - a) for p, a in zip(view.position, look_at))
    return CameraView(position, look_at, view.up, view.fov_deg)  # type: ignore[arg-type]


class ProjectorLayout:
    """One browser's projector layout and its `Projector` checkbox (built where the panel is).

    Args:
        client: the browser.
        guard: its session's guard: the checkbox's callback runs in it.
        own_view: the browser's own scene view now (its labels and camera are the layout's), or
            None while it follows the presenter.

    Attributes:
        on: the layout is in force.  style: the CSS element while on, else None.
        gui_checkbox: the panel's `Projector` checkbox.
    """

    def __init__(self, client: viser.ClientHandle, guard: Wrap, own_view: Callable[[], Any]) -> None:
        self.client = client
        self.on = False
        self.style: Any = None
        self._own_view = own_view
        gui: Any = client.gui  # viser's handles type `value` read-only; it is not
        tr = for_gui(gui)
        self.gui_checkbox = gui.add_checkbox(tr.gettext(PROJECTOR_WORDS[0]), False, hint=tr.gettext(PROJECTOR_WORDS[1]))
        self.gui_checkbox.on_update(guard("projector", lambda _event: self.set(bool(self.gui_checkbox.value))))

    def relabel(self, tr: Translator) -> None:
        """The checkbox in the language of `tr` (`app.i18n`; the browser chose another)."""
        self.gui_checkbox.label = tr.gettext(PROJECTOR_WORDS[0])
        self.gui_checkbox.hint = tr.gettext(PROJECTOR_WORDS[1])

    def set(self, on: bool) -> None:
        """Projector layout on or off: panel text >= 18 px, a narrower collapsible panel, 3D labels
        PROJECTOR_LABEL_SCALE times larger, the camera at `projector_view`."""
        on = bool(on)
        if on == self.on:
            return
        self.on = on
        if on:
            self.style = self.client.gui.add_html(PROJECTOR_CSS)
        elif self.style is not None:
            self.style.remove()
            self.style = None
        gui = self.client.gui
        gui.configure_theme(show_share_button=False, brand_color=BRAND_COLOR,
                            control_width="small" if on else "large")
        if on:  # docked on the right, narrow and collapsible: the 3D view keeps >= 70 % of 1024 px
            gui.main_panel.dock_right()
        else:
            gui.main_panel.float()
        if self.gui_checkbox.value != on:
            self.gui_checkbox.value = on
        view = self._own_view()
        if view is not None:
            self._scale_labels(view.root, PROJECTOR_LABEL_SCALE if on else 1.0 / PROJECTOR_LABEL_SCALE)
            self.reset_camera(view.room.scene.view)

    def fit_new_view(self, view: Any) -> None:
        """A new scene view of this browser: its labels take the layout's size, and its label
        layout knows whether the panel is docked beside the canvas (nothing covers it then)."""
        view.labels.docked = lambda: self.on
        if self.on:
            self._scale_labels(view.root, PROJECTOR_LABEL_SCALE)

    def reset_camera(self, view: CameraView) -> None:
        """Move the camera to the scene's camera `view`: centred for the projector layout, and on a
        narrow screen (a phone) the body centred above its bottom sheet (`narrow_view`)."""
        if self.on:
            view = projector_view(view)
        else:
            aspect = self.narrow_aspect()
            if aspect is not None:
                view = narrow_view(view, aspect)
        apply_camera(self.client, view)

    def narrow_aspect(self) -> float | None:
        """The width / height of the browser's view if it is narrow (`narrow_size`: a phone), else
        None (a wide view, or its size not reported)."""
        try:
            width, height = float(self.client.camera.image_width), float(self.client.camera.image_height)
        except (AttributeError, TypeError, ValueError):
            return None
        return width / height if height > 0.0 and narrow_size(width, height) else None

    def _scale_labels(self, root: str, factor: float) -> None:
        """Multiply the screen size of every 3D label under `root` (this browser's nodes)."""
        for name, handle in scene_nodes(self.client.scene).items():
            if name.startswith(root + "/") and hasattr(handle, "font_screen_scale"):
                handle.font_screen_scale = float(handle.font_screen_scale) * factor
