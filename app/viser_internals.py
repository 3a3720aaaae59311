"""The app's one seam to viser's private names: every one the app uses, checked, with a fallback.

viser's public API sends what the app draws, but some of the app's work needs what viser keeps
private: writing a pose without viser's per-assignment checks, finding a node's parents, a
panel's checkboxes, the send queue of a browser, and the websocket itself.  Every such name is
used here and nowhere else in `app/`; each is listed in `NEEDS` (owner, attribute, what it is
for) under the `Feature` that needs it.  `check()` looks every one up in the installed viser
(and the version, `VERSION` against `SUPPORTED`); at import a feature with something missing
is turned off, and `report()` (called once by `app.main.App`) says in the log what is off and
why.  A feature that is off uses viser's public path: slower, never wrong frames.

Features and what the app does without them:

- `FAST_SETTERS`: `set_wxyz`, `set_position`, `set_points`, `set_scale` store the value where
  the handle keeps it and queue the message the public setter would, unconditionally (the
  widgets send only what changed); off: the public setters (`handle.wxyz = ...`).
- `SCENE_NODES`: a scope's nodes by name (`scene_nodes`), the one walker of world poses
  (`world_pose`, `world_point`, `node_pose`, `node_world`), a node's removed flag and a label's props; off:
  no walker (`app.kit.draw.labels` shows every wanted label, with no layout), `remove_under` removes
  a subtree by replacing its root, `node_removed` is False.
- `PANEL_INPUTS`: a panel's inputs (and checkboxes) below given top-level handles (`panel_inputs`,
  `panel_checkboxes`), the folder or tab a control is in (`add_beside`: a refusal note goes
  right under its control), and each value a browser sends as it arrives (`on_browser_value`);
  off: None (`app.kit.view` looks through the view's attributes), `add_beside` adds in the
  container being built (the root, for a control bound after its folder), and nothing arrives
  (a bound control reads its handle when its callback runs).
- `FRAME_CAPTURE`: `app.wire` (a frame encoded once, in viser's wire format, written to the
  sockets): `divert_queue`, the interfaces, buffers, connections and event loop, the window
  envelope (`pack_window`); needs viser `SUPPORTED` (the wire builds viser's frames itself); off:
  `app.wire.Wire.attach` gives None and every change goes through viser, held together by
  `atomic_unless_captured` (viser's `atomic()`).
- `SEND_QUEUE`: `app.backpressure` sees what viser has not sent yet (`pending_messages`,
  `unsent_bytes`, `flush_all`); off: no skipping (time-based pacing) and `client.flush()`.

`tests/test_viser_seam.py` checks that nothing is missing with the installed viser, that no
other module of `app/` names a private viser attribute, and that the app serves frames with a
feature off.
"""

from __future__ import annotations

import asyncio
import contextlib
import dataclasses
import dis
import importlib
import logging
import threading
import typing
from collections.abc import Callable, Iterable, Iterator
from typing import Any

import numpy as np
import viser

from physics.quaternion import matrix_from_wxyz

__all__ = ["FAST_SETTERS", "FEATURES", "FRAME_CAPTURE", "NEEDS", "PANEL_INPUTS", "SCENE_NODES", "SEND_QUEUE",
           "SUPPORTED", "VERSION", "Feature", "Need", "add_beside", "atomic_unless_captured", "check", "client_buffer",
           "configure", "connection_closed", "divert_queue", "event_loop", "flush_all", "frame_capture",
           "in_frame_capture",
           "input_handle", "interface_of", "label_props", "live_connections", "message_buffer", "message_from_dict",
           "node_pose", "node_removed", "on_browser_value",
           "node_world", "pack_window", "panel_checkboxes", "panel_inputs", "pending_messages", "remove_under",
           "report",
           "scene_nodes", "set_points", "set_position", "set_scale", "set_wxyz", "unsent_bytes", "world_point",
           "world_pose"]

logger = logging.getLogger(__name__)

VERSION: str = str(getattr(viser, "__version__", "unknown"))
SUPPORTED = "1.1."  # the viser releases whose internals these are (pyproject pins viser to 1.1.x)


@dataclasses.dataclass
class Feature:
    """A use of viser's internals: its name, what the app does without it, whether it is on
    (and why not)."""

    name: str
    fallback: str
    on: bool = True
    why: str = ""


FAST_SETTERS = Feature("fast setters", "poses, points and scales go through viser's public setters")
SCENE_NODES = Feature("scene nodes", "labels are shown as wanted (no layout); a view's controls go with a "
                                     "replaced root")
PANEL_INPUTS = Feature("panel inputs", "a view's checkboxes are looked for in its own attributes, a "
                                      "control's refusal note sits where the view's panel is being built, and "
                                      "a bound control reads its handle's value when its callback runs")
FRAME_CAPTURE = Feature("frame capture", "frames go through viser's own sender, one atomic() block a view")
SEND_QUEUE = Feature("send queue", "the pacer goes by time alone; flushes are client.flush()")
FEATURES = (FAST_SETTERS, SCENE_NODES, PANEL_INPUTS, FRAME_CAPTURE, SEND_QUEUE)


@dataclasses.dataclass(frozen=True)
class Need:
    """One private name the app uses: `attribute` of `owner` (a dotted path in viser: a module,
    or a class whose attribute, dataclass field, annotation or constructor-set attribute it is)."""

    feature: Feature
    owner: str
    attribute: str
    purpose: str


_HANDLE = "viser._assignable_props_api.AssignablePropsBase"
_NODE_STATE = "viser._scene_handles._SceneNodeHandleState"
_SCENE_API = "viser._scene_api.SceneApi"
_GUI_STATE = "viser._gui_handles._GuiHandleState"
_HANDLER = "viser.infra._infra.WebsockMessageHandler"
_WEBSOCK_SERVER = "viser.infra._infra.WebsockServer"
_CLIENT_STATE = "viser.infra._infra._ClientHandleState"
_BUFFER = "viser.infra._async_message_buffer.AsyncMessageBuffer"
_MESSAGE = "viser.infra._messages.Message"

NEEDS: tuple[Need, ...] = (
    Need(FAST_SETTERS, "viser._messages", "SetOrientationMessage", "the message handle.wxyz = ... queues"),
    Need(FAST_SETTERS, "viser._messages", "SetPositionMessage", "the message handle.position = ... queues"),
    Need(FAST_SETTERS, "viser._messages", "SceneNodeUpdateMessage", "the message handle.points/.scale queue"),
    Need(FAST_SETTERS, _HANDLE, "_impl", "a handle's state"),
    Need(FAST_SETTERS, _NODE_STATE, "name", "the node's name"),
    Need(FAST_SETTERS, _NODE_STATE, "wxyz", "the stored orientation"),
    Need(FAST_SETTERS, _NODE_STATE, "position", "the stored position"),
    Need(FAST_SETTERS, _NODE_STATE, "props", "the stored points and scale"),
    Need(FAST_SETTERS, _NODE_STATE, "removed", "no writes to a removed node"),
    Need(FAST_SETTERS, _NODE_STATE, "api", "the scope the node lives in"),
    Need(FAST_SETTERS, _SCENE_API, "_queue_scene_message", "queue a node's message in its scope"),
    Need(SCENE_NODES, _SCENE_API, "_handle_from_node_name", "a scope's nodes by name (a node's parents)"),
    Need(SCENE_NODES, _HANDLE, "_impl", "a handle's state"),
    Need(SCENE_NODES, _NODE_STATE, "name", "the node's name (its parents' names)"),
    Need(SCENE_NODES, _NODE_STATE, "wxyz", "the node's orientation, read without a copy"),
    Need(SCENE_NODES, _NODE_STATE, "position", "the node's position, read without a copy"),
    Need(SCENE_NODES, _NODE_STATE, "visible", "the node's visibility"),
    Need(SCENE_NODES, _NODE_STATE, "removed", "the node was removed"),
    Need(SCENE_NODES, _NODE_STATE, "api", "the scope the node lives in"),
    Need(SCENE_NODES, _NODE_STATE, "props", "a label's text, size and anchor, read directly"),
    Need(SCENE_NODES, "viser._messages.LabelProps", "text", "a label's text"),
    Need(SCENE_NODES, "viser._messages.LabelProps", "font_screen_scale", "a label's size"),
    Need(SCENE_NODES, "viser._messages.LabelProps", "anchor", "a label's anchor"),
    Need(PANEL_INPUTS, "viser._gui_api.GuiApi", "_gui_input_handle_from_uuid", "a panel's inputs"),
    Need(PANEL_INPUTS, "viser._gui_api.GuiApi", "_container_handle_from_uuid", "a panel's folders and tabs"),
    Need(PANEL_INPUTS, _HANDLE, "_impl", "a handle's state"),
    Need(PANEL_INPUTS, _GUI_STATE, "uuid", "an element's id"),
    Need(PANEL_INPUTS, _GUI_STATE, "removed", "the element was removed"),
    Need(PANEL_INPUTS, _GUI_STATE, "parent_container_id", "the folder or tab an element is in"),
    Need(PANEL_INPUTS, _GUI_STATE, "sync_cb", "called with a browser's update as it arrives, before the callbacks"),
    Need(FRAME_CAPTURE, "viser._viser.ViserServer", "_websock_server", "the shared scene's interface"),
    Need(FRAME_CAPTURE, "viser._viser.ClientHandle", "_websock_connection", "a browser's own interface"),
    Need(FRAME_CAPTURE, _HANDLER, "queue_message", "what every message goes through (diverted by a wire)"),
    Need(FRAME_CAPTURE, _HANDLER, "get_message_buffer", "an interface's send buffer"),
    Need(FRAME_CAPTURE, _HANDLER, "atomic", "hand viser a frame's other messages in one block"),
    Need(FRAME_CAPTURE, _WEBSOCK_SERVER, "_live_connections", "the browsers' websockets (their transports)"),
    Need(FRAME_CAPTURE, _WEBSOCK_SERVER, "_client_state_from_id", "a browser's own send buffer"),
    Need(FRAME_CAPTURE, _WEBSOCK_SERVER, "_background_event_loop", "viser's event loop (the writes run on it)"),
    Need(FRAME_CAPTURE, _CLIENT_STATE, "message_buffer", "a browser's own send buffer"),
    Need(FRAME_CAPTURE, _BUFFER, "message_from_id", "what viser has not sent yet"),
    Need(FRAME_CAPTURE, _BUFFER, "generator_cursors", "how far each browser has read the shared buffer"),
    Need(FRAME_CAPTURE, _BUFFER, "message_counter", "the shared buffer's last message id"),
    Need(FRAME_CAPTURE, _MESSAGE, "as_serializable_dict", "a message as viser serialises it"),
    Need(FRAME_CAPTURE, _MESSAGE, "redundancy_key", "one latest value per node and property"),
    Need(FRAME_CAPTURE, _MESSAGE, "entity_type", "the node or element a message is about"),
    Need(FRAME_CAPTURE, _MESSAGE, "entity_id_field", "the node or element a message is about"),
    Need(FRAME_CAPTURE, _MESSAGE, "lifecycle_phase", "an update, a creation or a removal"),
    Need(FRAME_CAPTURE, _MESSAGE, "_subclass_from_type_string", "a message class by its type name (the bus)"),
    Need(FRAME_CAPTURE, _MESSAGE, "_from_serializable_dict", "a message's fields from its dict (the bus)"),
    Need(FRAME_CAPTURE, "viser.infra._infra", "_append_aligned_buffers", "a window's raw buffers, as viser "
                                                                          "lays them out"),
    Need(SEND_QUEUE, "viser._viser.ClientHandle", "_websock_connection", "a browser's interface"),
    Need(SEND_QUEUE, "viser._viser.ClientHandle", "_viser_server", "the server of a browser"),
    Need(SEND_QUEUE, "viser._viser.ViserServer", "_websock_server", "the websocket server"),
    Need(SEND_QUEUE, "viser.infra._infra.WebsockClientConnection", "_state", "a browser's connection state"),
    Need(SEND_QUEUE, _CLIENT_STATE, "message_buffer", "a browser's own send buffer"),
    Need(SEND_QUEUE, _HANDLER, "get_message_buffer", "an interface's send buffer"),
    Need(SEND_QUEUE, _BUFFER, "message_from_id", "messages not yet taken by the sender"),
    Need(SEND_QUEUE, _BUFFER, "done", "the connection is closed"),
    Need(SEND_QUEUE, _BUFFER, "flush_event", "wake the sender now"),
    Need(SEND_QUEUE, _BUFFER, "event_loop", "the loop the sender runs on"),
    Need(SEND_QUEUE, _WEBSOCK_SERVER, "_live_connections", "bytes waiting in a browser's socket"),
)


# ---------------------------------------------------------------------- the check
def _resolve(path: str) -> Any:
    """The module or class at the dotted `path` (None if it is not there)."""
    parts = path.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            found: Any = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        for name in parts[cut:]:
            found = getattr(found, name, None)
            if found is None:
                return None
        return found
    return None


def _set_in_init(cls: type, attribute: str) -> bool:
    """Some constructor of `cls` (or of a base) assigns `self.<attribute>`."""
    for klass in cls.__mro__:
        init = vars(klass).get("__init__")
        code = getattr(init, "__code__", None)
        if code is not None and any(i.opname == "STORE_ATTR" and i.argval == attribute
                                    for i in dis.get_instructions(code)):
            return True
    return False


def _has(owner: Any, attribute: str) -> bool:
    if not isinstance(owner, type):
        return hasattr(owner, attribute)
    if hasattr(owner, attribute):
        return True
    if dataclasses.is_dataclass(owner) and attribute in {f.name for f in dataclasses.fields(owner)}:
        return True
    if any(attribute in vars(klass).get("__annotations__", {}) for klass in owner.__mro__):
        return True
    return _set_in_init(owner, attribute)


def check(needs: Iterable[Need] = NEEDS) -> list[str]:
    """What of `needs` the installed viser lacks, one line each ("owner.attribute (feature:
    purpose)"); empty when everything is there.  The version is `VERSION` (see `SUPPORTED`)."""
    missing = []
    for need in needs:
        owner = _resolve(need.owner)
        if owner is None or not _has(owner, need.attribute):
            missing.append(f"{need.owner}.{need.attribute} ({need.feature.name}: {need.purpose})")
    return missing


def configure(needs: Iterable[Need] = NEEDS, version: str | None = None) -> list[str]:
    """Turn each feature on or off by `check(needs)` (and FRAME_CAPTURE off for a viser outside
    `SUPPORTED`); what is missing.  Run at import; tests run it again with a name taken away."""
    needs = tuple(needs)
    version = VERSION if version is None else version
    missing_by_feature: dict[str, list[str]] = {}
    for need in needs:
        if check((need,)):
            missing_by_feature.setdefault(need.feature.name, []).append(f"{need.owner}.{need.attribute}")
    for feature in FEATURES:
        missing = missing_by_feature.get(feature.name, [])
        if missing:
            feature.on, feature.why = False, "viser " + version + " lacks " + ", ".join(missing)
        elif feature is FRAME_CAPTURE and not version.startswith(SUPPORTED):
            feature.on, feature.why = False, f"viser {version} is not {SUPPORTED}x (the wire writes its format)"
        else:
            feature.on, feature.why = True, ""
    _REPORTED.clear()
    return [line for lines in missing_by_feature.values() for line in lines]


_REPORTED: list[bool] = []


def report() -> None:
    """Say in the log, once, every feature that is off, why and what the app does instead."""
    if _REPORTED:
        return
    _REPORTED.append(True)
    if all(feature.on for feature in FEATURES):
        logger.info("viser %s: every internal the app uses is there", VERSION)
    for feature in FEATURES:
        if not feature.on:
            logger.warning("viser internals: %s off (%s); %s", feature.name, feature.why, feature.fallback)


# ---------------------------------------------------------------------- fast setters
def _queue(handle: Any, message: Any) -> None:
    impl = handle._impl
    if impl.removed:
        raise RuntimeError(f"Cannot update the removed scene node {impl.name!r}.")
    impl.api._queue_scene_message(message)


def set_wxyz(handle: Any, wxyz: tuple[float, float, float, float]) -> None:
    """handle.wxyz = wxyz (a unit quaternion, w x y z, Python floats), sent even if unchanged."""
    if not FAST_SETTERS.on:
        handle.wxyz = wxyz
        return
    _queue(handle, _MESSAGES.SetOrientationMessage(handle._impl.name, wxyz))
    handle._impl.wxyz[:] = wxyz


def set_position(handle: Any, xyz: tuple[float, float, float]) -> None:
    """handle.position = xyz (Python floats), sent even if unchanged."""
    if not FAST_SETTERS.on:
        handle.position = xyz
        return
    _queue(handle, _MESSAGES.SetPositionMessage(handle._impl.name, xyz))
    handle._impl.position[:] = xyz


def set_points(handle: Any, points: np.ndarray) -> None:
    """handle.points = points, a float32 array of the node's points shape, sent even if unchanged."""
    if not FAST_SETTERS.on:
        handle.points = points
        return
    _queue(handle, _MESSAGES.SceneNodeUpdateMessage(handle._impl.name, {"points": points.copy()}))
    current = handle._impl.props.points
    if current.shape == points.shape:
        current[:] = points
    else:
        handle._impl.props.points = points.copy()


def set_scale(handle: Any, scale: tuple[float, float, float]) -> None:
    """handle.scale = scale (per-axis, Python floats), sent even if unchanged."""
    if not FAST_SETTERS.on:
        handle.scale = scale
        return
    _queue(handle, _MESSAGES.SceneNodeUpdateMessage(handle._impl.name, {"scale": scale}))
    handle._impl.props.scale = scale


# ---------------------------------------------------------------------- scene nodes
def scene_nodes(scene: Any) -> dict[str, Any]:
    """The nodes of a scope (`client.scene` or `server.scene`) by name (a copy); {} when
    SCENE_NODES is off."""
    if not SCENE_NODES.on:
        return {}
    return dict(scene._handle_from_node_name)


def node_removed(handle: Any) -> bool:
    """The scene node was removed (False when SCENE_NODES is off: it cannot be known)."""
    if not SCENE_NODES.on:
        return False
    return bool(handle._impl.removed)


def remove_under(scene: Any, root: str) -> None:
    """Remove every node of `scene` named under `root` + "/" (the node `root` itself stays)."""
    if SCENE_NODES.on:
        for name, handle in list(scene._handle_from_node_name.items()):
            if name.startswith(root + "/") and not handle._impl.removed:
                handle.remove()
        return
    # Public path: a node made under the same name replaces `root`; removing it removes its
    # subtree (viser removes the descendants by name).
    scene.add_frame(root, show_axes=False, visible=False).remove()


def label_props(handle: Any) -> tuple[str, float, str, bool]:
    """A label's (text, font_screen_scale, anchor, visible), read without viser's attribute
    lookup when SCENE_NODES is on."""
    if SCENE_NODES.on:
        impl = handle._impl
        props = impl.props
        return props.text, props.font_screen_scale, props.anchor, impl.visible
    return str(handle.text), float(handle.font_screen_scale), str(handle.anchor), bool(handle.visible)


Pose = tuple[tuple[float, float, float, float], tuple[float, float, float], bool]  # world wxyz, position, shown
_IDENTITY: Pose = ((1.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0), True)


def _rotate(wxyz: Any, v: Any) -> tuple[float, float, float]:
    """v turned by the unit quaternion (w, x, y, z) (Python floats): v + 2w (u × v) + 2 u × (u × v)."""
    w, x, y, z = wxyz
    vx, vy, vz = v
    cx, cy, cz = y * vz - z * vy, z * vx - x * vz, x * vy - y * vx
    ccx, ccy, ccz = y * cz - z * cy, z * cx - x * cz, x * cy - y * cx
    return (vx + 2.0 * (w * cx + ccx), vy + 2.0 * (w * cy + ccy), vz + 2.0 * (w * cz + ccz))


def _mul(a: Any, b: Any) -> tuple[float, float, float, float]:
    """The quaternion product a b (w, x, y, z), of Python floats."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw)


def node_world(name: str, nodes: dict[str, Any], cache: dict[str, Pose]) -> Pose:
    """The world pose of the node `name` of a scope whose nodes are `nodes` (name -> handle):
    its wxyz and position (Python floats) composed with its parents' (viser names are paths:
    "/a/b" hangs under "/a"; a path segment with no node is the identity), and whether it and
    every node above it are visible and not removed; the root "" is the identity.  Memoised in
    `cache` (one layout: nodes share their parents).  The one walker of world poses."""
    if not name:
        return _IDENTITY
    pose = cache.get(name)
    if pose is not None:
        return pose
    parent_wxyz, parent_at, parent_shown = node_world(name.rsplit("/", 1)[0], nodes, cache)
    node = nodes.get(name)
    if node is None:  # a path segment with no node of its own
        pose = (parent_wxyz, parent_at, parent_shown)
    else:
        impl = node._impl  # its wxyz and position: float64 arrays (tolist: Python floats, the same values)
        rx, ry, rz = _rotate(parent_wxyz, impl.position.tolist())
        pose = (_mul(parent_wxyz, impl.wxyz.tolist()), (rx + parent_at[0], ry + parent_at[1], rz + parent_at[2]),
                parent_shown and bool(impl.visible) and not impl.removed)
    cache[name] = pose
    return pose


def _walker_off() -> RuntimeError:
    return RuntimeError(f"world poses need viser's scene registry ({SCENE_NODES.why})")


def world_point(handle: Any, cache: dict[str, Pose] | None = None,
                parent: str | None = None) -> tuple[tuple[float, float, float], bool] | None:
    """The node's origin in the world [scene units] and whether every node above it is shown
    (its own visibility left out: a label layout sets it); None if it was removed.

    cache: the parents' world poses (`node_world`), shared between calls of one layout;
    parent: the node's parent's name, if known.  RuntimeError when SCENE_NODES is off."""
    if not SCENE_NODES.on:
        raise _walker_off()
    impl = handle._impl
    if impl.removed:
        return None
    if parent is None:
        parent = impl.name.rsplit("/", 1)[0]
    wxyz, at, shown = node_world(parent, impl.api._handle_from_node_name, {} if cache is None else cache)
    rx, ry, rz = _rotate(wxyz, impl.position.tolist())
    return (rx + at[0], ry + at[1], rz + at[2]), shown


def node_pose(handle: Any, cache: dict[str, Pose]) -> Pose | None:
    """The node's world pose (`node_world`: wxyz and position on Python floats, and whether it
    and every node above it are shown), memoised in `cache` with its parents' (one layout);
    None if it was removed.  RuntimeError when SCENE_NODES is off."""
    if not SCENE_NODES.on:
        raise _walker_off()
    impl = handle._impl
    if impl.removed:
        return None
    return node_world(impl.name, impl.api._handle_from_node_name, cache)


def world_pose(handle: Any) -> tuple[np.ndarray, np.ndarray]:
    """(R_world_node (3, 3), p_world (3,)) of the node, composed from its parents' poses as last
    set.  RuntimeError when SCENE_NODES is off."""
    if not SCENE_NODES.on:
        raise _walker_off()
    impl = handle._impl
    wxyz, at, _shown = node_world(impl.name, impl.api._handle_from_node_name, {})
    return matrix_from_wxyz(np.asarray(wxyz, dtype=float)), np.asarray(at, dtype=float)


# ---------------------------------------------------------------------- panel inputs
def panel_inputs(gui: Any, roots: Iterable[Any]) -> list[Any] | None:
    """The inputs (buttons, sliders, checkboxes, menus, fields) of the panel `gui` (a
    `client.gui`) that are top-level handles `roots` or sit in a folder or tab below one of
    them, not removed; None when PANEL_INPUTS is off."""
    if not PANEL_INPUTS.on:
        return None
    top = {handle._impl.uuid for handle in roots}
    containers = gui._container_handle_from_uuid

    def ours(container: str) -> bool:
        while container in containers and container not in top and container != "root":
            container = containers[container]._impl.parent_container_id
        return container in top

    return [handle for handle in list(gui._gui_input_handle_from_uuid.values())
            if not handle._impl.removed and (handle._impl.uuid in top or ours(handle._impl.parent_container_id))]


BESIDE_GAP = 1e-3
"""viser's `order` of what `add_beside` adds: this far after its control (siblings' orders differ by
0.01 or more: viser's counter counts 1 a handle, the app's own orders step by 0.01 at least)."""


def add_beside(gui: Any, handle: Any, add: Callable[[float], Any]) -> Any:
    """What `add(order)` adds to the panel `gui` (a `client.gui`), right under `handle`: in its
    folder or tab, at `order` just after `handle.order` (BESIDE_GAP).  Without PANEL_INPUTS, or
    for a control at the panel's root, `add` runs in the container being built now."""
    order = float(handle.order) + BESIDE_GAP
    container = None
    if PANEL_INPUTS.on:
        impl = getattr(handle, "_impl", None)
        parent = getattr(impl, "parent_container_id", "root")
        container = getattr(gui, "_container_handle_from_uuid", {}).get(parent) if parent != "root" else None
    if container is None or not hasattr(container, "__enter__"):
        return add(order)
    try:
        container.__enter__()
    except RuntimeError:  # its `with` block is open on this thread: the call is inside it already
        return add(order)
    try:
        return add(order)
    finally:
        container.__exit__(None, None, None)


def on_browser_value(handle: Any, take: Callable[[Any], None]) -> bool:
    """Call `take(value)` with each new value a browser sends for the input `handle`, on viser's
    event loop as the message arrives: before the handle's callbacks run on viser's thread pool,
    and whatever the server writes to the handle in between.  viser's own `sync_cb` (it shares a
    server-wide handle with the other browsers) still runs after it.  False (nothing will be
    taken) when PANEL_INPUTS is off."""
    state: Any = getattr(handle, "_impl", None)
    if not PANEL_INPUTS.on or not hasattr(state, "sync_cb"):
        return False
    shared = state.sync_cb

    def arrived(client_id: Any, updates: dict[str, Any]) -> None:
        if "value" in updates:
            take(updates["value"])
        if shared is not None:
            shared(client_id, updates)

    state.sync_cb = arrived
    return True


def panel_checkboxes(gui: Any, roots: Iterable[Any]) -> list[Any] | None:
    """The checkboxes among `panel_inputs(gui, roots)`; None when PANEL_INPUTS is off."""
    inputs = panel_inputs(gui, roots)
    return None if inputs is None else [handle for handle in inputs if isinstance(handle, viser.GuiCheckboxHandle)]


# ---------------------------------------------------------------------- frame capture
_FRAME = threading.local()  # .on: this thread is inside `frame_capture()`


class _FrameCapture:
    """`frame_capture()`'s context: a flag on this thread (a class, not a generator: it is
    entered every frame)."""

    def __enter__(self) -> None:
        _FRAME.on = True

    def __exit__(self, *exc: object) -> None:
        _FRAME.on = False


_FRAME_CAPTURE = _FrameCapture()


def frame_capture() -> _FrameCapture:
    """A frame of the app loop: within it, what this thread queues to a diverted interface
    (`divert_queue`) is held by the interface's wire until the frame ends."""
    return _FRAME_CAPTURE


def in_frame_capture() -> bool:
    """This thread is inside `frame_capture()`."""
    return bool(getattr(_FRAME, "on", False))


def interface_of(server: Any, client: Any | None = None) -> Any:
    """viser's message interface of the shared scene (`client` None) or of one browser."""
    return server._websock_server if client is None else client._websock_connection


def _diverted(owner: Any) -> bool:
    """The interface of `owner` (a `ViserServer` or a `ClientHandle`) goes through a wire."""
    interface = owner._websock_server if isinstance(owner, viser.ViserServer) else owner._websock_connection
    return "queue_message" in vars(interface)


@contextlib.contextmanager
def atomic_unless_captured(*owners: Any) -> Iterator[None]:
    """Hold a change's messages together: each owner's (`ViserServer` or `ClientHandle`)
    viser `atomic()`, except inside `frame_capture()` for an owner whose interface a wire holds
    (the wire hands the frame over at once)."""
    capture = FRAME_CAPTURE.on and in_frame_capture()
    with contextlib.ExitStack() as stack:
        for owner in owners:
            if not (capture and _diverted(owner)):
                stack.enter_context(owner.atomic())
        yield


def divert_queue(interface: Any, take: Callable[[Any], None]) -> Callable[[Any], None]:
    """Route every message queued to viser's `interface` through `take` (a wire's); returns
    viser's own `queue_message`, which `take` hands messages on to.

    The interface's buffer is woken on its event loop only (`wake_on_loop`)."""
    wake_on_loop(interface.get_message_buffer())
    own = interface.queue_message
    interface.queue_message = take
    return own


def wake_on_loop(buffer: Any) -> None:
    """Make `buffer.message_event.set()` safe from any thread.

    viser's `AsyncMessageBuffer.push` sets its `asyncio.Event` directly from the pushing thread;
    off the loop that iterates the event's waiters while the loop adds and removes them
    ("RuntimeError: deque mutated during iteration", seen under load). Off the loop, the set is
    handed to the loop (`call_soon_threadsafe`, which `push` schedules as well); on the loop it runs
    as before. Idempotent."""
    event = buffer.message_event
    if "set" in vars(event):
        return
    loop = buffer.event_loop
    own_set = event.set

    def set_on_loop() -> None:
        try:
            running = asyncio.get_running_loop()
        except RuntimeError:
            running = None
        if running is loop:
            own_set()
            return
        try:
            loop.call_soon_threadsafe(own_set)
        except RuntimeError:  # the loop is closed: nobody waits any more
            pass

    event.set = set_on_loop


def message_buffer(interface: Any) -> Any:
    """The interface's send buffer (viser's `AsyncMessageBuffer`): `message_from_id` (what it
    has not sent yet), `generator_cursors`, `message_counter`."""
    return interface.get_message_buffer()


def event_loop(server: Any) -> Any:
    """viser's event loop (None before the server runs)."""
    return server._websock_server._background_event_loop


def live_connections(server: Any) -> dict[int, Any]:
    """The browsers' websocket connections by client id (viser's own dict: read, never change
    it); each has `transport` and `protocol.state`."""
    return server._websock_server._live_connections


def input_handle(client: Any, uuid: str) -> Any | None:
    """`client`'s GUI input whose uuid is `uuid` (what the page's `<label for>` names), or None."""
    return client.gui._gui_input_handle_from_uuid.get(uuid)


def client_buffer(server: Any, client_id: int) -> Any | None:
    """The send buffer of one browser's own messages, or None if it is gone."""
    state = server._websock_server._client_state_from_id.get(client_id)
    return None if state is None else state.message_buffer


def pack_window(inner: bytes, compressed: bytes, buffers: list[memoryview]) -> bytes:
    """viser 1.1's window envelope (as its `_message_producer`): the sizes of the msgpack
    `inner` and of its zstd form `compressed` (2 x 8 bytes, little-endian), `compressed`, then
    the raw `buffers` 8-byte aligned."""
    parts: list[bytes | memoryview] = [len(inner).to_bytes(8, "little"), len(compressed).to_bytes(8, "little"),
                                       compressed]
    _INFRA._append_aligned_buffers(parts, buffers, 16 + len(compressed))
    return b"".join(parts)


def message_from_dict(mapping: dict[str, Any], allowed: Iterable[str]) -> Any:
    """A viser message rebuilt from `mapping`, a dict as `Message.as_serializable_dict` makes it
    (numpy arrays already put back in place of its buffer placeholders), its "type" one of the
    `allowed` message class names; the class comes from viser's own registry of message types,
    nothing is imported or executed by name.  A props dataclass comes back from its dict.
    ValueError for an unknown or disallowed type or fields that do not fit it."""
    kind = mapping.get("type")
    if not isinstance(kind, str) or kind not in set(allowed):
        raise ValueError(f"message type {kind!r} is not allowed")
    cls: Any = _INFRA_MESSAGES.Message._subclass_from_type_string().get(kind)
    try:
        fields = {f.name: f for f in dataclasses.fields(cls)}
    except TypeError:
        raise ValueError(f"viser has no message type {kind!r}") from None
    values = {key: value for key, value in mapping.items() if key != "type"}
    if not set(values) <= set(fields):
        raise ValueError(f"{kind}: unknown fields {sorted(set(values) - set(fields))}")
    try:
        hints = typing.get_type_hints(cls)
        for key, value in list(values.items()):
            hint = hints.get(key)
            if isinstance(value, dict) and isinstance(hint, type) and dataclasses.is_dataclass(hint):
                values[key] = hint(**value)
        values = cls._from_serializable_dict(values)
        late = {key: values.pop(key) for key in [k for k in values if not fields[k].init]}
        message = cls(**values)
    except (TypeError, ValueError, KeyError, AttributeError, AssertionError) as error:
        raise ValueError(f"{kind}: {error!r}") from None
    for key, value in late.items():
        setattr(message, key, value)
    return message


# ---------------------------------------------------------------------- send queue
def _client_buffer_of(client: Any) -> Any | None:
    try:
        return client._websock_connection.get_message_buffer()
    except AttributeError:
        return None


def pending_messages(client: Any) -> int | None:
    """Messages queued for a browser (a `ClientHandle`) that viser's sender has not taken into a
    window yet (`len` of a dict: no lock); None when SEND_QUEUE is off or the queue is not found."""
    if not SEND_QUEUE.on:
        return None
    try:
        table = client._websock_connection._state.message_buffer.message_from_id
    except AttributeError:
        table = getattr(_client_buffer_of(client), "message_from_id", None)
    return len(table) if isinstance(table, dict) else None


def connection_closed(client: Any) -> bool:
    """The browser's connection is gone (its buffer is done); False when SEND_QUEUE is off."""
    if not SEND_QUEUE.on:
        return False
    return bool(getattr(_client_buffer_of(client), "done", False))


def unsent_bytes(client: Any) -> int:
    """Bytes written to the browser's socket and not yet taken by the kernel; 0 if unknown."""
    if not SEND_QUEUE.on:
        return 0
    try:
        connection = client._viser_server._websock_server._live_connections[client.client_id]
        return int(connection.transport.get_write_buffer_size())
    except (AttributeError, KeyError, TypeError):
        return 0


def flush_all(clients: Iterable[Any]) -> None:
    """Wake viser's sender for all `clients` now, in one call on its loop (`client.flush()` a
    client when SEND_QUEUE is off or a client's buffer is not found)."""
    events: list[Any] = []
    loop: Any = None
    fallback: list[Any] = []
    for client in clients:
        buffer = _client_buffer_of(client) if SEND_QUEUE.on else None
        event = getattr(buffer, "flush_event", None)
        buffer_loop = getattr(buffer, "event_loop", None)
        if event is None or buffer_loop is None or (loop is not None and buffer_loop is not loop):
            fallback.append(client)
            continue
        loop = buffer_loop
        events.append(event)
    if events:

        def _set_all() -> None:
            for event in events:
                event.set()

        try:
            loop.call_soon_threadsafe(_set_all)
        except RuntimeError:  # loop closed: server stopping
            pass
    for client in fallback:
        with contextlib.suppress(Exception):
            client.flush()


# ---------------------------------------------------------------------- at import
configure()
_MESSAGES: Any = _resolve("viser._messages")
_INFRA: Any = _resolve("viser.infra._infra")
_INFRA_MESSAGES: Any = _resolve("viser.infra._messages")
