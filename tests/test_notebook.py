"""The worked example notebook (docs/lecture_notes.ipynb) executed as Jupyter does (nbclient, a
real kernel), and its two paths checked: live (the kernel serves the scene: a websocket client
gets the Heavy top at its preset Loop) and static (the notebook rendered to HTML by nbconvert holds
the recorded players, which load nothing from the network and play from the file in Chromium).
"""

from __future__ import annotations

import html
import math
import re
import struct
import threading
from pathlib import Path
from typing import Any

import nbclient
import nbformat
import pytest

NOTEBOOK = Path(__file__).resolve().parents[1] / "docs" / "lecture_notes.ipynb"
EXECUTE_TIMEOUT = 180  # [s] per cell, for a busy machine (the whole notebook takes ~10 s idle)

pytestmark = pytest.mark.browser



def _scene_words(port: int, wanted: tuple[bytes, ...], timeout: float = 30.0) -> set[bytes]:
    """Connect to the live app on `port` as a browser would (viser's websocket protocol) and
    return which of `wanted` appear in what it sends within `timeout` [s]."""
    import msgspec.msgpack
    import viser
    import zstandard
    from viser import _messages
    from websockets.sync.client import connect

    seen: set[bytes] = set()
    done = threading.Event()
    with connect(f"ws://127.0.0.1:{port}", subprotocols=[f"viser-v{viser.__version__}"],
                 max_size=None, open_timeout=timeout) as ws:
        ws.send(msgspec.msgpack.encode(_messages.ViewerCameraMessage(
            wxyz=(1.0, 0.0, 0.0, 0.0), position=(3.0, 3.0, 3.0), fov=math.radians(50.0), near=0.01,
            far=100.0, image_height=600, image_width=800, look_at=(0.0, 0.0, 0.0),
            up_direction=(0.0, 0.0, 1.0)).as_serializable_dict()))
        decompress = zstandard.ZstdDecompressor()
        try:
            while not done.is_set():
                frame = ws.recv(timeout=timeout)
                if not isinstance(frame, bytes) or len(frame) < 16:
                    continue
                inner_len, compressed_len = struct.unpack_from("<QQ", frame, 0)
                inner = decompress.decompress(frame[16:16 + compressed_len], max_output_size=inner_len)
                seen |= {word for word in wanted if word in inner}
                if len(seen) == len(wanted):
                    done.set()
        except TimeoutError:
            pass
    return seen


def _execute(live_check: Any) -> Any:
    """The notebook executed in a kernel; `live_check(outputs)` runs while the kernel still runs."""
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(notebook, timeout=EXECUTE_TIMEOUT, kernel_name="python3",
                                     resources={"metadata": {"path": str(NOTEBOOK.parents[1])}})
    with client.setup_kernel():
        for index, cell in enumerate(notebook.cells):
            client.execute_cell(cell, index)
        live_check(notebook)
    return notebook


def _shown(notebook: Any) -> list[str]:
    """The text/html of every output that shows a scene (app.notebook.show)."""
    return [output["data"]["text/html"] for cell in notebook.cells if cell.cell_type == "code"
            for output in cell.outputs if "rigid-body-lab-player" in output.get("data", {}).get("text/html", "")]


def test_the_example_notebook_runs_live_and_renders_its_players(browser: Any, tmp_path: Path) -> None:
    from nbconvert import HTMLExporter

    from app.notebook import PLAYER_MARK

    def live(notebook: Any) -> None:
        outputs = _shown(notebook)
        assert len(outputs) == 2, "the Free body and the Heavy top"
        port = int(re.search(r'u="http://127\.0\.0\.1:(\d+)/"', outputs[1]).group(1))  # the Heavy top's
        seen = _scene_words(port, (b"Heavy top", b"Loop", b"Play"))
        assert seen == {b"Heavy top", b"Loop", b"Play"}, f"the live scene's panel: only {seen} seen"

    notebook = _execute(live)
    errors = [o for c in notebook.cells if c.cell_type == "code" for o in c.outputs if o.output_type == "error"]
    assert not errors, errors
    text = "".join(o.get("text", "") for c in notebook.cells if c.cell_type == "code" for o in c.outputs)
    assert "a flip every 3.92" in text and "loop" in text
    assert "viser" not in text, "viser's start and stop panels stay out of the cells' output"

    body, _ = HTMLExporter().from_notebook_node(notebook)
    page_path = tmp_path / "lecture_notes.html"
    page_path.write_text(body, encoding="utf-8")
    players = re.findall(r'<iframe [^>]*class="rigid-body-lab-player"[^>]*srcdoc="([^"]*)"', body)
    assert len(players) == 2
    for escaped in players:
        player = html.unescape(escaped)
        assert PLAYER_MARK in player
        remote = re.findall(r'(?:src|href)\s*=\s*["\']?(?:https?:)?//', player)
        assert not remote, f"the player loads from the network: {remote[:3]}"

    # Rendered without a kernel (the kernel and its servers are gone): the player plays from the file.
    page = browser.new_page(viewport={"width": 1000, "height": 900})
    try:
        page.route(re.compile(r"^https?://(?!127\.0\.0\.1)"), lambda route: route.abort())  # no network
        page.goto(page_path.as_uri(), wait_until="domcontentloaded")
        frame = page.frame_locator("iframe.rigid-body-lab-player").last
        frame.locator("canvas").first.wait_for(state="attached", timeout=60_000)
        src = page.locator("iframe.rigid-body-lab-player").last.get_attribute("src")
        assert src is None, "no live app answers, so the frame keeps the player"
    finally:
        page.close()
