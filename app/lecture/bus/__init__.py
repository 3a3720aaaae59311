"""One lecture across processes: what followers on another process see, through Redis.

**The design, and why.**  The presenting process (the *source*) already draws its presenter's
room once per frame into viser's shared scene (`server.scene`, under LIVE_ROOT, the pointer
too).  The bus taps the messages queued to that shared interface (`divert_queue`, in front of
the app's `Wire`) and publishes them once per frame, as msgpack of viser's own message dicts
(`Message.as_serializable_dict`, numpy arrays as raw buffers; `SceneBatch`), culled as viser culls (one value
per node and property).  Every other process decodes them into viser message objects of an
allowlisted set of scene types (`ALLOWED`; names under LIVE_ROOT only;
`app.viser_internals.message_from_dict` takes the class from viser's own registry: nothing is
imported, executed or unpickled) and queues them into *its* shared scene inside its app loop's
frame, so its `Wire` encodes each frame once for all its followers and viser's persistent buffer
serves its late joiners exactly as on one process.  Sending the scene's messages, not simulation
snapshots, keeps one simulation and one drawing per lecture (the other processes do no physics
for the lecture) and makes a remote follower's scene the same messages a local follower gets.

- Order and gaps: the scene batches carry a sequence number; a process that joins late or sees
  a gap asks (`ASK`, "resync") and the source publishes its shared scene's whole state (`Replica`:
  the last create and the last value of every node under LIVE_ROOT, kept from the same tap);
  the one that asked removes the nodes the state no longer has and applies it.
- The hall's state (the followers' status as data, `FollowerStatus`; the caption, the title) goes
  as a small message every FOLLOW_PERIOD, the presenter's camera (with its aspect, so each
  follower's view is framed for its screen as on one process) at most every CAMERA_PERIOD when it
  moved, and again after a resync (a process that came late has never heard it); a "call_back"
  when the presenter calls everyone back.  Another process shows it as a
  `app.lecture.lectern.RemoteShow` (its `Lectern` then has a live show without a local room).
- The presenter's open plot tab (`Lectern.room_plot`: uPlot charts as float32 columns and their
  properties, Markdown) goes when it changed, at most every MIRROR_PERIOD and at least every
  PLOT_RESEND_S; another process's followers see it copied as on one process (`RemoteShow.plot`).
- Stopped and left: the source says "stopped" or "left" when its presenter stops or leaves (or
  its process stops); a process that hears nothing from a live source for LEASE_S takes it that
  the presenter has left (its process ended).  The last state stays on the followers' screens.
- Explore on another process: it asks the source ("explore", with a request id); the source
  encodes its live room ONCE for all the requests of a frame (`encode_room`, the kit's codec),
  stores the bytes under ROOM_KEY + n for ROOM_TTL_MS and answers with n; the asker decodes it
  (`decode_room`: checked, bit for bit the presenter's state).
- A lecture survives its source's death.  Each presenter's start is a new lecture (`lecture_id`,
  carried in its scene batches); its room left on the shared screen is kept in Redis (LAST_KEY)
  with that id, so only that lecture's followers copy it (an older lecture's room, kept
  LAST_TTL_S, is never offered for a newer one).  While it presents, the source also publishes
  its room without history ("keep", `encode_room(history=False)`, under 0.5 ms, up to ~280 kB:
  ~250 kB/s for Heavy top playing) at once when its run or transport changes (`_room_mark`),
  else every KEEP_PERIOD_S when it changed; every process keeps the last one of the lecture it shows
  (`Kept`), and each scene batch says the room's time ("st").  Explore when the source does not
  answer (killed: SIGKILL says nothing) gives, the best first: the room the lecture left in Redis
  (exact: stored when its presenter stopped or left, after the last keep), else the kept copy
  advanced to the time of the last batch this process drew (at most MAX_CATCH_UP_S; the same
  integrator, frames of 1/60 s) and paused, else a fresh room of the same scene; the last two
  with a note saying so (`fetch_room_noted`).
- Audience: each process writes its (following, exploring) into the hash AUDIENCE_KEY every
  FOLLOW_PERIOD with the time and its followers' kinds of screen (`Lectern.follower_screens`);
  the presenter's badge adds the others' fresh counts, and its shared labels are laid out for
  their screens too (`Lectern.remote_screens`: a phone on another process sees no overlap).

Channels and keys start with `app.cluster.KEY_PREFIX`.  Everything read from Redis is one of the
messages of `app.cluster.messages` (msgpack), decoded with its type and checked (types, sizes,
names) before use; a malformed message is logged and dropped, and changes nothing.
The bus is made only with `create_server(redis_url=...)`: a one-process app has none.

The package, by role: `core` (`Bus`, the roles wired to the app loop and the reader thread),
`source` (`Publisher`: this process's presenter's room published), `follow` (`Following`: a
presenter on another process followed), `shared` (`SharedScene`: its nodes in this process's
shared scene, the pointer's markers and every node taken away again), `rooms` (`RemoteRooms`:
Explore here of its room), `audience` (`AudienceBoard`), `wire` (scene messages as bytes),
`values` (the hall's values as messages), `link` (channels, keys, periods; the Redis client).
"""

from __future__ import annotations

from app.lecture.bus.core import Bus
from app.lecture.bus.follow import Kept
from app.lecture.bus.link import ASK, AUDIENCE_KEY, CHANNEL, LAST_KEY, LEASE_S
from app.lecture.bus.wire import ALLOWED, BusError, Replica, cull, decode_batch, encode_batch

__all__ = ["ALLOWED", "ASK", "AUDIENCE_KEY", "CHANNEL", "LAST_KEY", "LEASE_S", "Bus", "BusError", "Kept", "Replica",
           "cull", "decode_batch", "encode_batch"]
