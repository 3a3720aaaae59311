"""Nothing leaves the picture: the Moving frame's particles, played for a minute, stay in the view
and outside the panel in the three layouts a lecture uses, and a preset's traces go with it.

The picture of each layout is the camera the browser is given and the panel's rectangle over it:

- desktop 1280x800: the scene's `CameraView` (`MovingFrameView.view`, put there by the session's
  `reset_camera`); viser's floating panel on the right (measured: x from 881 px, 15 to 768 px);
- projector 1024x768: `projector_view` of it; the panel is docked on the right, so the 3D view
  is the 764x768 px left of it (measured) and nothing lies over it;
- phone follower 390x844: the presenter's desktop camera fitted to the phone (`fitted_camera`);
  the follower's one-line panel at the bottom right (measured: x from 124 px, y from 700 px).

The motion is modelled here, vectorised, from the preset's numbers (`FrameMotion` for C′; the
free particle on its straight line in C until it reaches the rim, then at rest in C′ there; the
particle at rest in C′; the spring particle by SciPy's DOP853), checked against the scene's own
simulation at a few moments, and projected every 0.1 s for 60 s.  One browser test proves that
the browser's camera is the one modelled (its camera as it reports it, and particle pixels where
the model projects them) and that a preset chosen while playing leaves no trace of the last.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from PIL import Image
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from test_browser import choose

from app.hall.projector import projector_view
from app.kit.core.common import CameraView
from app.kit.draw.screen import project
from app.lecture.lectern import fitted_camera
from app.scenes import SCENES
from app.scenes.moving_frame import MovingFrameSetup, MovingFrameSimulation, MovingFrameView
from physics.moving_frames import space_from_body
from physics.quaternion import matrix_from_wxyz

SECONDS = 60.0  # [s] of play checked
SAMPLE = 0.1  # [s] between checked moments
MARGIN_PX = 12.0  # a particle's drawn radius and a little more
PRESETS = MovingFrameView.presets()


def _layouts(view: CameraView) -> dict[str, tuple[CameraView, int, int, tuple[float, float, float, float] | None]]:
    """name -> (camera, width, height [px] of the 3D view, the panel's rectangle over it (x0, y0,
    x1, y1) [px] or None)."""
    position, look_at = fitted_camera(view.position, view.look_at, 1280 / 800, 390 / 844,
                                      math.radians(view.fov_deg), view.up)
    return {
        "desktop 1280x800": (view, 1280, 800, (881.0, 15.0, 1265.0, 768.0)),
        "projector 1024x768": (projector_view(view), 764, 768, None),
        "phone follower 390x844": (CameraView(position, look_at, view.up, view.fov_deg), 390, 844,
                                   (124.0, 700.0, 390.0, 844.0)),
    }


def modelled_points(setup: MovingFrameSetup, times: np.ndarray) -> np.ndarray:
    """(T, 4, 3) [m] in C at `times` (T,) [s]: C′'s origin and the particles (free, at rest in C′,
    on a spring), from the setup's numbers."""
    motion = setup.motion
    frames = [motion.at(float(t)) for t in times]
    a = np.array([f.a for f in frames])
    R = np.array([f.R_space_body for f in frames])
    x_body0, v_body0 = setup.initial_body()
    x0, v0 = space_from_body(frames[0], x_body0, v_body0)
    free = x0[0] + times[:, None] * v0[0]
    rim = setup.value("disc_radius")

    def past_rim(t: float) -> float:  # |x′| − rim of the free particle on its straight line
        frame = motion.at(t)
        return float(np.linalg.norm((x0[0] + t * v0[0] - frame.a) @ frame.R_space_body)) - rim

    if np.linalg.norm(x_body0[0]) < rim:
        reached = np.flatnonzero([past_rim(float(t)) >= 0.0 for t in times])
        if reached.size:
            i = int(reached[0])
            t_rim = brentq(past_rim, float(times[i - 1]), float(times[i]), xtol=1e-9)
            frame = motion.at(t_rim)
            place = (x0[0] + t_rim * v0[0] - frame.a) @ frame.R_space_body
            free[i:] = a[i:] + R[i:] @ place
    rider = a + R @ setup.rider_body
    k_over_m = setup.k / setup.mass

    def spring(t: float, y: np.ndarray) -> np.ndarray:
        frame = motion.at(t)
        return np.concatenate([y[3:], -k_over_m * (y[:3] - frame.a - frame.R_space_body @ setup.anchor_body)])

    solution = solve_ivp(spring, (0.0, float(times[-1])), np.concatenate([x0[2], v0[2]]), method="DOP853",
                         t_eval=times, rtol=1e-9, atol=1e-11)
    assert solution.success, solution.message
    return np.stack([a, free, rider, solution.y[:3].T], axis=1)


def _outside(points_px: np.ndarray, width: int, height: int,
             panel: tuple[float, float, float, float] | None) -> np.ndarray:
    """Which projected points (N, 2) [px] leave the view or touch the panel (MARGIN_PX around)."""
    x, y = points_px[:, 0], points_px[:, 1]
    bad = ~((x >= MARGIN_PX) & (x <= width - MARGIN_PX) & (y >= MARGIN_PX) & (y <= height - MARGIN_PX))
    if panel is not None:
        x0, y0, x1, y1 = panel
        bad |= (x > x0 - MARGIN_PX) & (x < x1 + MARGIN_PX) & (y > y0 - MARGIN_PX) & (y < y1 + MARGIN_PX)
    return bad


@pytest.mark.parametrize("preset", PRESETS, ids=[p.name for p in PRESETS])
def test_every_moving_frame_preset_for_60_s_keeps_its_particles_in_the_view_and_off_the_panel(preset) -> None:  # type: ignore[no-untyped-def]
    setup = MovingFrameSetup(preset.params, preset.angles_deg)
    times = np.arange(0.0, SECONDS + SAMPLE / 2, SAMPLE)
    points = modelled_points(setup, times)
    # The model is the scene's motion: the simulation agrees at a few moments (RK4 at 1/240 s
    # against DOP853 for the spring: ~1e-8 m; the rim's stop found by both where the line crosses it).
    sim = MovingFrameSimulation(setup)
    for t in (1.5, 3.0):
        sim.advance(t - sim.t)
        i = int(round(t / SAMPLE))
        np.testing.assert_allclose(sim.x, points[i, 1:], atol=1e-6, err_msg=f"{preset.name} at t = {t} s")
        np.testing.assert_allclose(sim.frame.a, points[i, 0], atol=1e-12)
    flat = points.reshape(-1, 3)
    names = ("C′'s origin", "the free particle", "the particle at rest in C′", "the spring particle")
    for layout, (camera, width, height, panel) in _layouts(MovingFrameView.view).items():
        pixels, _depth = project(camera, flat, width, height)
        bad = _outside(pixels, width, height, panel).reshape(points.shape[:2])
        if bad.any():
            i, k = (int(n) for n in np.argwhere(bad)[0])
            x, y = pixels.reshape(*points.shape[:2], 2)[i, k]
            pytest.fail(f"{preset.name}, {layout}: {names[k]} at t = {times[i]:.1f} s is drawn at "
                        f"({x:.0f}, {y:.0f}) px: off the view or under the panel {panel}")


# ---------------------------------------------------------------------------- through the page
PANEL_JS = """(uuid) => { let e = document.getElementById(uuid);
  while (e && !String(e.className).includes('Paper-root')) e = e.parentElement;
  const r = e.getBoundingClientRect(); return [r.x, r.y, r.x + r.width, r.y + r.height]; }"""


def _old_points_held(view) -> list[str]:  # type: ignore[no-untyped-def]
    """The trace nodes of the view that hold points which are not on its simulation's traces now
    (a hidden node must hold only its idle segment; a shown one only points of the current run)."""
    from app.kit.draw.widgets import TraceLines

    found = []
    for name, value in vars(view).items():
        lines = [v for v in (value if isinstance(value, list) else [value]) if isinstance(v, TraceLines)]
        traces = getattr(view.sim, name, None)
        for k, tl in enumerate(lines):
            trace = traces[k]
            kept = trace.points(trace.first, trace.count).astype(np.float32)
            for j, node in enumerate(tl._nodes):
                points = np.asarray(node.points).reshape(-1, 3)
                if not node.visible and np.all(points == 0.0):
                    continue
                distance = np.min(np.linalg.norm(points[:, None, :] - kept[None, :, :], axis=-1), axis=1)
                if not len(kept) or np.max(distance) > 1e-3:
                    found.append(f"{name}[{k}] node {j} ({'shown' if node.visible else 'hidden'})")
    return found


def _colour_near(pixels: np.ndarray, x: float, y: float, colour: tuple[int, int, int], half: int = 8) -> bool:
    """A pixel within `half` px of (x, y) [px] has about `colour` (a shaded sphere: within 70)."""
    patch = pixels[max(0, int(y) - half):int(y) + half + 1, max(0, int(x) - half):int(x) + half + 1]
    return bool(np.any(np.linalg.norm(patch - np.array(colour), axis=-1) < 70.0))


@pytest.mark.browser
def test_the_browser_frames_the_modelled_picture_and_a_preset_leaves_no_old_trace(app, page, wait_until, tmp_path
                                                                                   ) -> None:  # type: ignore[no-untyped-def]
    """Through the page: Moving frame chosen in the dropdown; its camera (as the browser reports
    it) is the scene's view; `Accelerating line` played 4 s and paused shows its three particles
    where that camera projects them, left of the panel (whose rectangle is the one modelled).
    Then, while it plays, `Turntable` is chosen: at once no trace node holds a point of the old
    run, and once the new one plays, only points of the new run are drawn."""
    from test_browser import open_app

    from app.scenes.moving_frame.view import PARTICLE_COLORS

    session = open_app(page, app)
    choose(page, session.gui_scene, "Moving frame")
    page.get_by_text("Moving frame C′ (memo").wait_for(timeout=30_000)
    view = MovingFrameView.view
    camera, width, height, panel = _layouts(view)["desktop 1280x800"]
    reported = session.client.camera

    def camera_is_the_view() -> bool:
        return (np.allclose(reported.position, view.position, atol=1e-6)
                and np.allclose(reported.look_at, view.look_at, atol=1e-6)
                and abs(float(reported.fov) - math.radians(view.fov_deg)) < 1e-6)

    wait_until(camera_is_the_view, timeout=15.0)
    assert (reported.image_width, reported.image_height) == (width, height)
    x0, y0, x1, y1 = page.evaluate(PANEL_JS, session.gui_scene._impl.uuid)
    assert panel is not None and x0 >= panel[0] - 1 and y0 >= panel[1] - 1 and x1 <= panel[2] + 1, (x0, y0, x1, y1)

    page.get_by_role("button", name="Accelerating line").click()
    wait_until(lambda: session.room.sim.preset == "Accelerating line", timeout=10.0)
    page.get_by_role("button", name="Play", exact=True).click()
    sim = session.room.sim
    wait_until(lambda: sim.t > 4.0, timeout=60.0)
    page.get_by_role("button", name="Pause", exact=True).click()
    wait_until(lambda: not session.room.playing, timeout=10.0)
    drawn = np.array([session.scene.particle_drawn(k) for k in range(3)])  # C′ coordinates, as sent
    points = sim.frame.a + drawn @ sim.frame.R_space_body.T
    time.sleep(1.0)  # the browser draws the paused frame
    path = tmp_path / "accelerating_line.png"
    page.screenshot(path=str(path))
    pixels = np.asarray(Image.open(path).convert("RGB"), dtype=float)
    projected, _ = project(camera, points, width, height)
    assert not _outside(projected, width, height, panel).any(), projected
    for (x, y), colour in zip(projected, PARTICLE_COLORS):
        assert _colour_near(pixels, x, y, colour), f"no particle of colour {colour} at ({x:.0f}, {y:.0f}) px"

    page.get_by_role("button", name="Play", exact=True).click()
    wait_until(lambda: sim.t > 6.0 and _old_points_held(session.scene) == [], timeout=60.0)
    page.get_by_role("button", name="Turntable").click()  # while playing
    wait_until(lambda: sim.preset == "Turntable", timeout=10.0)
    with session.room.lock:
        assert _old_points_held(session.scene) == []
    page.get_by_role("button", name="Play", exact=True).click()
    wait_until(lambda: sim.t > 1.5, timeout=60.0)
    with session.room.lock:
        assert _old_points_held(session.scene) == []
    assert session.error_count == 0, session.last_error


# ---------------------------------------------------------------------------- the other scenes
def _moving_points(scene: object, root: str) -> np.ndarray:
    """World points (N, 3) of what a scene draws that moves: the centre of every shown ball
    (icosphere) and the corners of every shown simple mesh's box, under `root`."""
    from app.viser_internals import node_world, scene_nodes

    nodes = scene_nodes(scene)
    cache: dict = {}
    points = []
    for name, handle in nodes.items():
        kind = type(handle).__name__
        if not name.startswith(root + "/") or kind not in ("IcosphereHandle", "MeshHandle"):
            continue
        wxyz, at, shown = node_world(name, nodes, cache)
        if not shown:
            continue
        if kind == "IcosphereHandle":
            points.append(np.asarray(at, dtype=float)[None, :])
            continue
        vertices = np.asarray(handle.vertices, dtype=float) * np.asarray(handle.scale, dtype=float)
        lo, hi = vertices.min(axis=0), vertices.max(axis=0)
        corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
        points.append(np.asarray(at, dtype=float) + corners @ matrix_from_wxyz(wxyz).T)
    return np.concatenate(points) if points else np.zeros((0, 3))


ELSEWHERE = {
    "Moving frame": "its particles against the modelled picture, above",
    "Inertia": "nothing moves: no Play",
}
"""Scenes this check leaves out, and why; every other scene of the registry is checked."""
OTHER_SCENES = tuple(title for title in SCENES if title not in ELSEWHERE)


def test_the_scenes_left_out_are_scenes() -> None:
    stale = [title for title in ELSEWHERE if title not in SCENES]
    assert not stale, f"ELSEWHERE of tests/test_in_the_picture.py names no scene of app.scenes.SCENES: {stale}"


@pytest.mark.timeout(900)  # a minute of every preset: Constrained particles 49 s quiet, past 300 s beside two `yes`
@pytest.mark.parametrize("title", OTHER_SCENES)
def test_the_other_scenes_keep_their_bodies_in_the_view_and_off_the_panel(manual, title: str) -> None:
    """Every preset of the scene, played for up to a minute of simulated time in coarse frames
    (1 s), its moving balls and meshes (scenery that stays put is left out) projected through
    each layout's camera at each frame."""
    session = manual.session
    session.select_scene(title)
    view_class = SCENES[title]
    failures = []
    for preset in view_class.presets():
        session.apply_preset(preset.name)
        session.play()
        samples = []
        for _ in range(int(SECONDS)):
            session.tick(1.0)
            if session.simulation.t >= SECONDS or not session.room.playing:
                break
            with session.lock:
                samples.append(_moving_points(session.client.scene, session.scene.root))
        if len({len(sample) for sample in samples}) != 1:
            continue  # nodes shown and hidden on the way: no point-to-point comparison
        track = np.stack(samples)  # (samples, N, 3)
        moving = np.max(np.linalg.norm(track - track[:1], axis=-1), axis=0) > 1e-6  # scenery stays
        for layout, (camera, width, height, panel) in _layouts(view_class.view).items():
            pixels, _ = project(camera, track[:, moving].reshape(-1, 3), width, height)
            bad = _outside(pixels, width, height, panel)
            if bad.any():
                failures.append((layout, f"{preset.name}, {layout}: {int(bad.sum())} of {bad.size} points, "
                                          f"e.g. {pixels[bad][0].round()} px"))
    assert not failures, failures
