"""Every angle a readout prints in degrees is in (−180°, 180°], however long the run: the
simulations keep φ and ψ continuous (unwrapped), the texts wrap them (`app.kit.core.common.format_deg`).
The sliders' own values are not readouts and are not checked here.
"""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np
import pytest

from app.kit.core.common import format_deg
from app.kit.panel.gui import Readout

_NUMBER = r"[-+−]?\d+(?:\.\d+)?(?:e[-+]?\d+)?"
_DEGREES = re.compile(rf"({_NUMBER})\s*°(?!/)")  # "12.5°", not "12.5°/s"
Q_NAME, Q_COLUMN = 15, 11  # the Lagrange tab's rows: a 15-character name, then 11-character columns


def degree_values(text: str) -> list[float]:
    """The numbers printed as angles in degrees: before a ° (not °/s), and the Lagrange tab's
    q row (fixed columns; a number too wide for its column reads as inf)."""
    values = [float(m.replace("−", "-")) for m in _DEGREES.findall(text)]
    for line in text.splitlines():
        if line.startswith("q [deg]"):
            for k in range(3):
                cell = line[Q_NAME + k * Q_COLUMN:Q_NAME + (k + 1) * Q_COLUMN]
                try:
                    values.append(float(cell))
                except ValueError:
                    values.append(math.inf)
    return values


def test_degree_values_finds_angles_and_not_rates() -> None:
    text = ("φ = 12.50°  θ = 3°  ψ = −179.99° · rate 20°/s\n"
            f"{'q [deg]':<15}{2336.5:11.5f}{45.0:11.5f}{-10.0:11.5f}\n"
            "q [deg]         2302.55975   60.0000023944.27155")  # columns run together
    assert degree_values(text)[:6] == [12.5, 3.0, -179.99, 2336.5, 45.0, -10.0]
    assert degree_values(text)[6:] == [2302.55975, 60.0, 23944.27155]


@pytest.mark.parametrize(("angle", "decimals", "text"), [
    (2336.5, 1, "176.5"), (-179.999, 2, "180.00"), (180.0, 2, "180.00"), (-180.0, 0, "180"),
    (540.0, 1, "180.0"), (-0.001, 2, "0.00"), (359.4, 0, "-1"), (-190.0, 2, "170.00"),
])
def test_format_deg_wraps_after_rounding(angle: float, decimals: int, text: str) -> None:
    assert format_deg(angle, decimals) == text


def _texts(view: Any) -> str:
    """The text of every Markdown element of a view's panel (readouts, status, notes)."""
    seen: set[int] = set()
    texts: list[str] = []

    def visit(value: Any, depth: int) -> None:
        if id(value) in seen or depth > 3:
            return
        seen.add(id(value))
        if isinstance(value, Readout):
            value = value.handle
        content = getattr(value, "content", None)
        if isinstance(content, str) and type(value).__name__ == "GuiMarkdownHandle":
            texts.append(content)
            return
        if isinstance(value, (list, tuple)):
            for item in value:
                visit(item, depth + 1)
        elif isinstance(value, dict):
            for item in value.values():
                visit(item, depth + 1)
        elif type(value).__module__.startswith("app."):
            for item in vars(value).values() if hasattr(value, "__dict__") else ():
                visit(item, depth + 1)

    visit(view, 0)
    return "\n".join(texts)


def _assert_wrapped(view: Any, where: str) -> list[float]:
    text = _texts(view)
    values = degree_values(text)
    outside = [v for v in values if not -180.0 < v <= 180.0]
    assert not outside, f"{where}: degree values outside (−180, 180]: {outside}\n{text}"
    return values


def test_heavy_top_readouts_wrap_angles_after_a_long_run(manual) -> None:
    """φ of the steady precession passes 2000° (unwrapped in the simulation); every tab's text
    prints it in (−180°, 180°] (the Lagrange tab showed φ = 2336.5°)."""
    session = manual.session
    session.select_scene("Heavy top")
    session.apply_preset("Steady")
    view = session.scene
    sim = view.sim
    while abs(math.degrees(sim.angles[0])) < 2300.0 or abs(math.degrees(sim.angles[2])) < 2300.0:
        sim.advance(0.1)
    assert abs(math.degrees(sim.angles[0])) > 2000.0
    checked = 0
    for tab in ("Readout", "Lagrange", "Plots", "Setup"):
        view.tabs.show(tab)
        session.room.refresh()
        session.tick(1.0)  # the throttled readouts (10 Hz) and plots are due
        checked += len(_assert_wrapped(view, f"Heavy top, {tab} tab"))
    assert checked >= 6  # φ θ ψ in the Readout tab and the Lagrange tab's q row at least
    assert session.error_count == 0, session.last_error


def test_free_body_and_moving_frame_readouts_wrap_angles(manual) -> None:
    session = manual.session
    for title, preset in (("Free body", "Disc"), ("Moving frame", "Turntable"), ("Euler angles", "D = 1")):
        session.select_scene(title)
        session.apply_preset(preset)
        view = session.scene
        session.play()
        for _ in range(40):
            session.tick(1.0 / 4.0)  # ten seconds, a readout each frame
        tabs = getattr(view, "tabs", None)
        for tab in (tabs.names if tabs is not None else (None,)):
            if tab is not None:
                view.tabs.show(tab)
                session.room.refresh()
                session.tick(0.5)
            _assert_wrapped(view, f"{title} {preset}, tab {tab}")
        assert np.isfinite(session.simulation.t)
    assert session.error_count == 0, session.last_error
