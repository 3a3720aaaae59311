"""Lean frames (issue 16) for the rigid-body scenes: what a playing frame sends, and how much.

The byte counts encode a frame's messages exactly as viser 1.1 does on the wire (16-byte header,
zstd level 1 over msgpack, raw numpy buffers after it), with the probe's fixed timestamp.
"""

from __future__ import annotations

import math

import msgspec
import numpy as np
import pytest
import zstandard
from viser.infra import _async_message_buffer

from app.kit.core.trace import Trace
from app.kit.draw.widgets import HEAD_EVERY, LENGTH_RTOL, POSE_QUANTUM, TraceLines, Vector, quantized, z_onto

DT = 1.0 / 60.0
FPS = 60.0

# Measured on the branch lean-rigid (kB/s, own room, 60 fps): Free body 15.5-17.1, Heavy top
# 18.5-21.1, Poinsot 18.2-20.8 (was 25-42).  The bounds leave ~15 % for noise and catch a return
# of per-frame label positions, points arrays or whole traces (each 3-20 kB/s).
BUDGET_KBPS = {"Free body": 19.5, "Heavy top": 24.0, "Poinsot": 24.0}
MAX_MESSAGES_PER_FRAME = 7.0  # averaged over the frames measured (GUI and labels at 5-10 Hz included)
CASES = [("Free body", "Dzhanibekov"), ("Free body", "Disc"), ("Heavy top", "Steady"), ("Heavy top", "Loop"),
         ("Poinsot", "Dzhanibekov"), ("Poinsot", "Flat lamina")]


def _frame_bytes(messages: list) -> int:  # type: ignore[type-arg]
    """Bytes of one websocket message carrying `messages`, as viser 1.1 encodes a window."""
    if not messages:
        return 0
    buffers: list = []  # type: ignore[type-arg]
    serialized = tuple(m.as_serializable_dict(buffers) for m in messages)
    inner = msgspec.msgpack.encode({"messages": serialized, "timestampSec": 1.0,
                                    "binaryBufferLengths": tuple(b.nbytes for b in buffers)})
    return 16 + len(zstandard.ZstdCompressor(level=1).compress(inner)) + sum(b.nbytes for b in buffers)


@pytest.mark.parametrize(("title", "preset"), CASES)
def test_a_playing_rigid_scene_stays_within_its_byte_budget(manual, monkeypatch, title: str, preset: str) -> None:
    session = manual.session
    session.select_scene(title)
    session.apply_preset(preset)
    session.play()
    manual.tick(0.5)  # past the first frames (labels laid out, sliders synced)
    pushed: list = []  # type: ignore[type-arg]
    original = _async_message_buffer.AsyncMessageBuffer.push

    def push(self, message):  # type: ignore[no-untyped-def]
        pushed.append(message)
        return original(self, message)

    monkeypatch.setattr(_async_message_buffer.AsyncMessageBuffer, "push", push)
    frames = []
    for _ in range(120):
        start = len(pushed)
        session.tick(DT)
        frames.append(pushed[start:])
    kbps = sum(_frame_bytes(f) for f in frames) / len(frames) * FPS / 1e3
    per_frame = sum(len(f) for f in frames) / len(frames)
    assert kbps <= BUDGET_KBPS[title], f"{title}/{preset}: {kbps:.1f} kB/s"
    assert per_frame <= MAX_MESSAGES_PER_FRAME, f"{title}/{preset}: {per_frame:.2f} messages a frame"
    names = {getattr(m, "name", "") for f in frames for m in f}
    assert not any(name.endswith(("omega_label", "/L_label")) for name in names)  # labels ride on their arrows
    assert session.error_count == 0, session.last_error


def test_z_onto_turns_z_onto_the_direction_about_a_horizontal_axis() -> None:
    rng = np.random.default_rng(16)
    for d in [*rng.normal(size=(20, 3)), (0.0, 0.0, 1.0), (0.0, 0.0, -1.0), (1e-9, 0.0, -1.0)]:
        d = np.asarray(d, dtype=float) / np.linalg.norm(d)
        w, x, y, z = z_onto(d)
        assert z == 0.0 and math.isclose(w * w + x * x + y * y, 1.0, rel_tol=1e-12)
        turned_z = np.array([2 * (x * z + w * y), 2 * (y * z - w * x), w * w - x * x - y * y + z * z])
        np.testing.assert_allclose(turned_z, d, atol=1e-9)


def test_quantized_values_are_multiples_of_the_quantum_within_half_of_it() -> None:
    values = (0.123456789, -0.987654321, 0.5, 1e-9)
    q = quantized(values, POSE_QUANTUM)
    for v, x in zip(values, q):
        assert abs(v - x) <= 0.5 * POSE_QUANTUM and (x / POSE_QUANTUM).is_integer()


def _recorder(server, monkeypatch):  # type: ignore[no-untyped-def]
    sent: list[tuple[str, str]] = []
    api = server.scene
    original = api._queue_scene_message

    def recording(message):  # type: ignore[no-untyped-def]
        updates = getattr(message, "updates", None)
        sent.append((getattr(message, "name", ""), ",".join(updates) if updates else type(message).__name__))
        return original(message)

    monkeypatch.setattr(api, "_queue_scene_message", recording)
    return sent


def test_a_vector_that_turns_sends_one_orientation_and_its_length_only_beyond_LENGTH_RTOL(
        server, monkeypatch) -> None:
    vector = Vector(server.scene, "/lean/omega", (230, 90, 0), "ω")
    vector.update(np.array([0.0, 1.5, 0.0]))  # exact (a refresh): shown, turned, stretched
    np.testing.assert_allclose(vector.segment, [[0, 0, 0], [0, 1.5, 0]], atol=1e-12)
    sent = _recorder(server, monkeypatch)
    turn = 0.3
    vector.update(1.5 * np.array([math.sin(turn), math.cos(turn), 0.0]), quantum=POSE_QUANTUM)
    assert sent == [("/lean/omega", "SetOrientationMessage")]  # the label and head ride on it
    sent.clear()
    vector.update(1.5 * (1.0 + 0.5 * LENGTH_RTOL) * np.array([math.sin(turn), math.cos(turn), 0.0]),
                  quantum=POSE_QUANTUM)
    assert sent == []  # the same at display resolution: nothing
    vector.update(1.5 * (1.0 + 3.0 * LENGTH_RTOL) * np.array([math.sin(turn), math.cos(turn), 0.0]),
                  quantum=POSE_QUANTUM)
    assert sorted(sent) == [("/lean/omega/s", "scale"), ("/lean/omega/t", "SetPositionMessage")]
    tip = vector.segment[1]
    np.testing.assert_allclose(np.linalg.norm(tip), 1.5 * (1.0 + 3.0 * LENGTH_RTOL), rtol=1e-12)
    np.testing.assert_allclose(tip / np.linalg.norm(tip), [math.sin(turn), math.cos(turn), 0.0], atol=2 * POSE_QUANTUM)


def test_trace_lines_send_each_complete_chunk_once_and_the_head_every_HEAD_EVERY_frames(server, monkeypatch) -> None:
    trace = Trace(seconds=100.0, spacing=1.0, chunk_points=7)  # stride 6; a ring of 20 nodes
    lines = TraceLines(server.scene, "/lean/trace", (200, 0, 120), trace)
    sent = _recorder(server, monkeypatch)
    for k in range(40):  # a point a frame, every frame lazy (playing)
        trace.add(float(k), np.array([k, 0.0, 0.0]))
        lines.sync(trace, lazy=True)
    points = [name for name, what in sent if what == "points"]
    # Chunks 0..5 complete (each sent when complete, and at most once more as the growing head, at
    # most every HEAD_EVERY frames); the head (chunk 6, 4 points) waits.
    complete = [f"/lean/trace/{c}" for c in range(6)]
    assert all(1 <= points.count(name) <= 2 for name in complete)
    assert len(points) <= len(complete) + 40 // HEAD_EVERY
    lines.sync(trace)  # a refresh: the head at once
    np.testing.assert_array_equal(lines.shown_segments()[-1], [[38.0, 0, 0], [39.0, 0, 0]])
    assert lines.point_count == 40
