"""`SharedScene`: another process's nodes in this process's shared scene (what a following
process applies of the source's scene, and takes away again)."""

from __future__ import annotations

from collections.abc import Callable

from app.lecture.bus.wire import Replica, SceneMessage, removal
from app.lecture.lectern import LIVE_ROOT, POINTER_ROOT

__all__ = ["SharedScene"]


class SharedScene:
    """The source's scene as applied here, through `queue` (viser's own `queue_message` of the
    shared scene, behind the app's wire): scene batches kept for the frame (`apply_frame`),
    whole states at once; the pointer's markers and every node taken away again.

    `applied`: what was applied (the nodes to drop on a resync).  `resyncs`: whole states applied.
    """

    def __init__(self, queue: Callable[[SceneMessage], None]) -> None:
        self.queue = queue
        self.applied = Replica()
        self.pending: list[SceneMessage] = []  # scene messages taken in, for this frame (`apply_frame`)
        self.resyncs = 0

    def apply(self, messages: list[SceneMessage]) -> None:
        """A frame's batch: kept for `apply_frame`."""
        for message in messages:
            self.applied.add(message)
        self.pending.extend(messages)

    def apply_frame(self) -> None:
        """Queue the scene batches taken in into the shared scene (the app loop, inside its frame:
        the wire encodes them once for every follower)."""
        pending, self.pending = self.pending, []
        for message in pending:
            self.queue(message)

    def apply_full(self, messages: list[SceneMessage]) -> None:
        """The source's whole state: the nodes it no longer has go, then everything is applied
        (what was kept for this frame is older: dropped)."""
        self.pending = []
        state = Replica()
        for message in messages:
            state.add(message)
        gone = self.applied.nodes() - state.nodes()
        for name in sorted(gone, key=len):
            if not any(name.startswith(other + "/") for other in gone):
                self.queue(removal(name))
        self.applied = state
        for message in messages:
            self.queue(message)
        self.resyncs += 1

    def drop_pointer(self) -> None:
        """The pointer's markers of a source that went silent (killed: it never removes them) go
        from the shared scene; the rest stays, the last state it showed."""
        markers = [name for name in self.applied.nodes() if name.startswith(POINTER_ROOT + "/")
                   and "/" not in name[len(POINTER_ROOT) + 1:]]
        for name in sorted(markers):
            message = removal(name)
            self.queue(message)
            self.applied.add(message)

    def clear(self) -> None:
        """Remove every node applied here (this process presents now): each by name, the deepest
        first.  (One removal of LIVE_ROOT is not enough: the new view's first node of that name
        supersedes it in viser's buffers, and the old nodes under it stayed on this process's
        followers' screens, and in what a late browser is sent.)"""
        names = self.applied.nodes()
        for name in sorted(names, key=lambda n: (-n.count("/"), n)):
            self.queue(removal(name))
        if names:
            self.queue(removal(LIVE_ROOT))
        self.applied = Replica()
