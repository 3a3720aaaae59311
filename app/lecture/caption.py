"""The lesson's caption: the running step's words in a band along the edge of a browser's 3D view.

A lecture hall reads the lesson from the wall, not from a panel: the caption is one HTML element
of the browser's panel (`gui.add_html`) that CSS fixes to the window over the 3D canvas
(`position: fixed`), so it stays put while the camera moves and takes no room in the panel.
On a wide screen it runs along the bottom, left of the panel: the scenes are z-up, their bodies
and arrows rise from the middle of the view and the floor grid fills its bottom.  On a phone
held upright it runs along the top, where the view is free (the phone's panel sits at the
bottom).  It ignores the mouse (`pointer-events: none`): a drag on it turns
the camera as a drag on the scene does.

Sizes, in CSS px (the projector's back row decides them):

- CAPTION_PX on a laptop or desktop;
- PROJECTOR_CAPTION_PX in the projector layout (`app.hall.projector.PROJECTOR_CSS` adds
  CAPTION_PROJECTOR_RULES): slide-making guides ask for body text of at least 24 pt on a
  720 pt-high slide, 1/30 of the screen's height; 1/30 of a 1024x768 projector's 768 px is
  25.6 px, so 28 px;
- PHONE_CAPTION_PX on a view at most PHONE_MAX_PX wide (a phone held upright), where the band
  spans the whole width.

On a wider screen the band ends PANEL_GAP_PX short of the right edge, where viser's floating
panel sits (PROJECTOR_PANEL_GAP_PX: the docked projector panel).

Who writes it: `app.hall.lesson_runner.LessonRunner` in the browser running a lesson (its
`Caption` checkbox; for a presenter it decides for the room), and the lectern in every
follower's (`app.lecture.follower.Follower`, whose own `Caption` checkbox hides it there).
"""

from __future__ import annotations

import html
from typing import Any

__all__ = ["CAPTION_CLASS", "CAPTION_PROJECTOR_RULES", "CAPTION_PX", "PANEL_GAP_PX", "PHONE_CAPTION_PX",
           "PHONE_MAX_PX", "PROJECTOR_CAPTION_PX", "PROJECTOR_PANEL_GAP_PX", "Caption", "caption_html"]

CAPTION_CLASS = "rbl-caption"  # the band's CSS class (tests find it by this)
CAPTION_PX = 22  # [CSS px] the step's words on a laptop
PROJECTOR_CAPTION_PX = 28  # [CSS px] in the projector layout: >= 1/30 of a 768 px-high screen
PHONE_CAPTION_PX = 15  # [CSS px] on a phone held upright
PHONE_MAX_PX = 600  # [CSS px] a view at most this wide gets the phone's band
PANEL_GAP_PX = 420  # [CSS px] the band ends this far from the right edge (viser's floating panel)
PROJECTOR_PANEL_GAP_PX = 290  # [CSS px] ... in the projector layout (the docked panel)

_STYLE = f"""<style>
.{CAPTION_CLASS} {{ position: fixed; bottom: 0; left: 0; right: {PANEL_GAP_PX}px; z-index: 100;
  padding: 6px 16px 8px 16px; font-size: {CAPTION_PX}px; line-height: 1.25; color: #111;
  background: rgba(255, 255, 255, 0.92); border-top: 2px solid rgba(200, 110, 0, 0.7);
  border-top-right-radius: 8px; pointer-events: none; overflow-wrap: break-word; }}
.{CAPTION_CLASS} .rbl-caption-head {{ display: block; font-size: 0.62em; color: #7a4300;
  font-weight: 600; margin-bottom: 2px; }}
@media (max-width: {PHONE_MAX_PX}px) {{ .{CAPTION_CLASS} {{ top: 0; bottom: auto; right: 0;
  font-size: {PHONE_CAPTION_PX}px; padding: 4px 10px 6px 10px; border-top: none;
  border-bottom: 2px solid rgba(200, 110, 0, 0.7); border-radius: 0; }} }}
</style>"""

CAPTION_PROJECTOR_RULES = (
    f".{CAPTION_CLASS} {{ font-size: {PROJECTOR_CAPTION_PX}px !important; "
    f"right: {PROJECTOR_PANEL_GAP_PX}px !important; }}"
)
"""CSS the projector layout adds (inside its <style>): the projector's caption size."""


def caption_html(head: str, text: str) -> str:
    """The band's HTML: `head` (the lesson and step, small) over `text` (the step's words),
    both plain text (escaped here); "" for no text."""
    if not text:
        return ""
    return (f'{_STYLE}<div class="{CAPTION_CLASS}" role="note" aria-label="lesson caption">'
            f'<span class="rbl-caption-head">{html.escape(head)}</span>{html.escape(text)}</div>')


class Caption:
    """One browser's caption band (an HTML element of its panel, hidden while it has no text).

    Args:
        gui: the browser's panel (`client.gui`); the element is added where the panel is being
            built (its place in the panel does not matter: CSS puts it over the view).

    Attributes:
        head, text: what it shows ("" and "": nothing).  handle: the HTML element.
    """

    def __init__(self, gui: Any) -> None:
        self.head = ""
        self.text = ""
        self.handle = gui.add_html("", visible=False)

    @property
    def shown(self) -> bool:
        return bool(self.text)

    def show(self, head: str, text: str) -> None:
        """Show `text` under `head` ("" text: hide the band); unchanged words are not sent."""
        head, text = str(head), str(text)
        if (head, text) == (self.head, self.text):
            return
        self.head, self.text = head, text
        if text:
            self.handle.content = caption_html(head, text)
        if self.handle.visible != bool(text):
            self.handle.visible = bool(text)

    def remove(self) -> None:
        self.handle.remove()
