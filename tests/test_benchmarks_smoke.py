"""Smoke runs of the benchmark scripts (benchmarks/ws_client.py, load_clients.py, frame_cost.py).

They check that the scripts work and produce numbers (fps > 0, finite costs, the simulation
really advanced), never timing thresholds: those depend on the machine and are the scripts'
own output.  The websocket client's decoding is checked against what a plain viser server was
told to send (independent of the lecture app).
"""

from __future__ import annotations

import math
import time

import numpy as np
import pytest

from benchmarks.ws_client import POSE_MESSAGE_TYPES, ViserClient, decode_frame


@pytest.fixture
def plain_server():
    """A bare viser server on loopback (no lecture app), stopped after the test."""
    import viser

    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        yield server
    finally:
        server.stop()


def test_decode_frame_rejects_truncated_frames() -> None:
    with pytest.raises(ValueError):
        decode_frame(b"\x00" * 8)
    header = (10).to_bytes(8, "little") + (50).to_bytes(8, "little")  # says 50 bytes follow
    with pytest.raises(ValueError):
        decode_frame(header + b"\x00" * 10)


def test_client_decodes_scene_gui_and_poses_and_drives_a_slider(plain_server) -> None:
    """Binary arrays, GUI tables and pose counts match what the server was told to send; a
    GuiUpdateMessage found by label fires the server callback with the value sent."""
    server = plain_server
    points = np.arange(2 * 2 * 3, dtype=np.float32).reshape(2, 2, 3) / 7.0
    seen: list[float] = []
    connected: list[object] = []
    server.on_client_connect(lambda client: connected.append(client))
    client = ViserClient(server.get_port())
    try:
        client.state.wait_for(lambda: connected, 5.0)
        handle = connected[0]
        handle.scene.add_line_segments("/probe/lines", points, (255, 0, 0))
        slider = handle.gui.add_slider("probe slider", 0.0, 10.0, 0.5, 1.0)
        slider.on_update(lambda _event: seen.append(slider.value))
        frame = handle.scene.add_frame("/probe/body")
        wxyz_sent = [(math.cos(a / 2), 0.0, 0.0, math.sin(a / 2)) for a in np.linspace(0.1, 1.0, 5)]
        for wxyz in wxyz_sent:
            frame.wxyz = wxyz
            time.sleep(1.0 / 30.0)  # slower than viser's 60 Hz flush: no pose is culled

        element = client.wait_for_label("probe slider", 5.0)
        assert element.type == "GuiSliderMessage" and element.value == 1.0
        assert element.props["min"] == 0.0 and element.props["max"] == 10.0
        client.set_value("probe slider", 7.5)
        client.state.wait_for(lambda: seen, 5.0)
        assert seen == [7.5]

        def arrived():
            stats = client.state.pose_snapshot().get("/probe/body")
            return stats if stats and np.allclose(stats.last_wxyz, wxyz_sent[-1], rtol=0, atol=1e-12) else None

        stats = client.state.wait_for(arrived, 5.0)
        # Counted, one per assignment; viser may cull a superseded pose if a flush is late.
        assert 2 <= stats.orientations <= 5
        assert not any(m["type"] in POSE_MESSAGE_TYPES for _t, _s, m in client.state.messages)

        lines = [m for _t, _s, m in client.state.messages
                 if m["type"] == "LineSegmentsMessage" and m["name"] == "/probe/lines"]
        assert len(lines) == 1
        blob = lines[0]["props"]["points"]
        decoded = np.frombuffer(blob["data"], dtype=np.dtype(blob["dtype"])).reshape(points.shape)
        np.testing.assert_array_equal(decoded, points)  # exact: raw float32 bytes
        assert not client.state.errors
    finally:
        client.close()


def test_load_clients_smoke() -> None:
    """2 clients, 2 s: each receives frames of its moving body; server CPU and memory read."""
    from benchmarks.load_clients import format_table, run_load

    result = run_load(clients=2, seconds=2.0, scene="Free body", warmup=0.5)
    assert len(result.fps) == 2
    assert all(fps > 0.0 for fps in result.fps), result.fps
    assert all(kb > 0.0 for kb in result.kbytes_per_s)
    assert math.isfinite(result.server_cpu_percent) and result.server_cpu_percent > 0.0
    assert result.server_rss_mib > 10.0  # an interpreter with viser loaded, in MiB
    assert result.decode_errors == 0
    assert "| Free body | 2 |" in format_table([result])


def test_frame_cost_smoke() -> None:
    """100 unpaced ticks of the heavy top: finite positive costs; the motion really advanced."""
    from benchmarks.frame_cost import format_table, measure_scene, tick_medians

    result = measure_scene("Heavy top", frames=100, paced=False, warmup=5)
    assert len(result.tick_ms) == len(result.physics_ms) == 100
    for values in (result.tick_stats, result.physics_stats):
        assert all(math.isfinite(v) and v > 0.0 for v in values)
    assert result.sim_time_advanced_s > 0.0
    table = format_table([result])
    assert "| Heavy top | 100 |" in table
    # --rounds reads the medians back from the printed table (3 decimals)
    assert tick_medians(table) == {"Heavy top": pytest.approx(result.tick_stats[0], abs=5e-4)}


def test_drag_latency_owes_each_pixel_change_to_one_mouse_step() -> None:
    """benchmarks/drag_latency.py: a change answers the first step before it that has no answer
    yet; a step with no change after it by the end of the drag is infinite."""
    from benchmarks.drag_latency import _latencies, _quantile

    moves = [0.0, 250.0, 500.0, 750.0]  # [ms]
    changes = [40.0, 60.0, 290.0, 760.0]  # the second change (60 ms) is still the first step's picture
    assert _latencies(moves, changes) == pytest.approx([0.04, 0.04, 0.26, math.inf])
    assert _latencies(moves, []) == [math.inf] * 4  # the body moved only after the thumb stopped
    assert _quantile([0.1, 0.2, 0.3, math.inf], 0.5) == 0.2 and _quantile([0.1, math.inf], 0.95) == math.inf
