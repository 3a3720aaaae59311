"""What the lectern's parts share: a browser's seat (`Seat`, `Mode`), another worker's show
(`RemoteShow`) and what the parts read of the lectern (`Stage`)."""

from __future__ import annotations

import dataclasses
import enum
from collections.abc import Callable
from typing import Any, Protocol

import viser

from app.kit.core.room import Room
from app.kit.draw.labels import Screen
from app.lecture.follower import FollowerStatus, Hall

__all__ = ["FOLLOW_PERIOD", "Mode", "RemoteShow", "Seat", "Stage"]

FOLLOW_PERIOD = 0.5  # [s] the followers' panels, the other panels' lecture part and a refusal's words
# are written again this often (they are many)


class Mode(enum.StrEnum):
    """What a browser's session shows."""

    OWN = "own"  # its own room (exploring alone)
    PRESENTING = "presenting"  # its room, live for everyone who follows
    FOLLOWING = "following"  # the live room, read only


class Seat(Protocol):
    """What the lectern needs of a browser's session (`app.session.Session` is one)."""

    client: viser.ClientHandle
    client_id: int
    closed: bool
    mode: Mode
    own_folders: tuple[Any, ...]
    """The session's own folders (projector, notes, lecture), which a collapsed follower's panel hides."""

    def guard(self, where: str, fn: Callable[..., Any]) -> Callable[..., Any]:
        """`fn` run under the session's locks, its errors shown in its panel, never raised."""
        ...

    def following_by_default(self) -> bool:
        """True if a new presenter should pull this browser along."""
        ...

    def follow(self) -> None:
        """Follow the presenter (the lectern calls it when a presenter starts)."""
        ...

    def explore(self) -> None:
        """Leave the presenter with an exact copy of the live room (the follower's button)."""
        ...

    def report_error(self, where: str, error: BaseException) -> None:
        """Log `error` and show it in the session's panel."""
        ...

    def lesson_text(self) -> str:
        """The presenter's current lesson step, or ""."""
        ...

    def lesson_words(self) -> dict[str, dict[str, str]]:
        """Its lesson step's line and caption in the other languages: {code: {English: words}} ({} for none)."""
        ...

    def stop_presenting(self) -> None:
        """Stop presenting (the lectern calls it when this browser's lock was lost)."""
        ...

    def lecture_changed(self) -> None:
        """Show the lecture's state in the panel (who follows, a call back): called by the lectern,
        outside the session's guard (it only writes widgets, and only what changed)."""
        ...

    def caption_words(self) -> tuple[str, str]:
        """(head, words) of the presenter's lesson caption; ("", "") for none (`app.lecture.caption`)."""
        ...


@dataclasses.dataclass
class RemoteShow:
    """What a presenter on another process shows, as this process's followers see it
    (`app.lecture.bus` writes it; the shared scene's nodes come through the bus too).

    Attributes:
        worker: the presenting process's worker id.  hall: LIVE, STOPPED or LEFT (the lectern's:
            `Lectern.remote_ended`).
        title: the scene's title.
        status: the followers' status as the presenting process made it (`FollowerStatus`; its
            hall follows `hall`); before the first one comes, the title alone.
        caption: (head, words) of the lesson caption.
        plot: (tab, elements) of the presenter's open plot tab (`Lectern.room_plot`; elements
            `app.lecture.room_plot.ChartCopy` / `MarkdownCopy`), ("", ()) for none.
        camera: the presenter's camera (position, look_at, up [scene units], fov [rad], aspect
            [width / height]) or None before it is known.
    """

    worker: str
    hall: Hall = Hall.LIVE
    title: str = ""
    status: FollowerStatus = FollowerStatus()
    caption: tuple[str, str] = ("", "")
    plot: tuple[str, tuple[Any, ...]] = ("", ())
    camera: dict[str, Any] | None = None

    def __post_init__(self) -> None:
        if not self.status.title:
            self.status = FollowerStatus(hall=self.hall, title=self.title)

    def shown_status(self) -> FollowerStatus:
        """`status` in this process's `hall` (a presenter who stopped or left, whatever the last
        status heard said)."""
        return self.status.ended(self.hall)


class Stage(Protocol):
    """What the lectern's parts read of it (`app.lecture.lectern.Lectern` is one): who presents, what the
    shared screen shows, and the browsers."""

    presenter: Seat | None
    hall: Hall
    remote: RemoteShow | None
    live_view: Any
    remote_screens: Callable[[], list[Screen]]
    """The kinds of follower's screen on the other processes."""

    @property
    def live_room(self) -> Room | None:
        """The room on the shared screen now (the presenter's, or the last state one left)."""
        ...

    @property
    def someone_presents(self) -> bool:
        """A presenter presents, on this process or another."""
        ...

    def seats(self) -> list[Seat]:
        """The open sessions."""
        ...
