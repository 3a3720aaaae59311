"""The Inertia scene (memo §3): the tensor, its principal frame and the parallel-axis term against
formulas written out here; the cases of (3.8) said in words and a frame that does not flicker;
meshes: each bad kind refused with its reason, a box against its closed form; "Spin it"."""

from __future__ import annotations

import io
import types

import numpy as np
import pytest
import trimesh

import app.scenes.inertia as inertia_scene
from physics.inertia import box_inertia

ATOL = 1e-12


def tensor(masses, positions, about) -> np.ndarray:  # type: ignore[no-untyped-def]
    """Σ m (|x|² 𝟙 − x xᵀ), x from `about` (3.5), written out."""
    out = np.zeros((3, 3))
    for m, x in zip(masses, np.asarray(positions, dtype=float) - about):
        out += m * (float(x @ x) * np.eye(3) - np.outer(x, x))
    return out


def _inertia(manual):  # type: ignore[no-untyped-def]
    manual.session.select_scene("Inertia")
    return manual.session.scene


def test_tensor_principal_frame_and_parallel_axis_term(manual) -> None:
    view = _inertia(manual)
    manual.session.apply_preset("L-shape")
    sim = view.sim
    props = sim.properties()
    com = (sim.masses[:, None] * sim.positions).sum(axis=0) / sim.masses.sum()
    np.testing.assert_allclose(props["com"], com, atol=ATOL)
    np.testing.assert_allclose(props["I_O"], tensor(sim.masses, sim.positions, com), atol=ATOL)
    assert abs(props["I_O"][0, 1]) > 0.1  # products of inertia: x, y are not principal
    axes, moments = props["axes"], props["moments"]
    assert np.linalg.det(axes) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(axes.T @ props["I_O"] @ axes, np.diag(moments), atol=1e-12)
    view.gui_about.value = (1.0, -0.5, 0.25)  # O leaves the centre of mass
    props = sim.properties()
    O = np.array([1.0, -0.5, 0.25])
    np.testing.assert_allclose(props["I_O"], tensor(sim.masses, sim.positions, O), atol=ATOL)
    d = com - O
    np.testing.assert_allclose(props["parallel"], 4.0 * (d @ d * np.eye(3) - np.outer(d, d)), atol=ATOL)
    content = view.readout.handle.content
    assert "m(|d|²𝟙 − d dᵀ)" in content and "I_cm" in content
    np.testing.assert_allclose(np.asarray(view.O_frame.position), O, atol=1e-12)


def test_the_cases_of_3_8_are_said_and_the_frame_does_not_flicker(manual) -> None:
    view = _inertia(manual)
    manual.session.apply_preset("On a line")
    notes = " ".join(view.sim.properties()["notes"])
    assert "zero" in notes and "one line through O" in notes
    manual.session.apply_preset("Dumbbell")
    assert "Two moments are equal" in view.readout.handle.content
    manual.session.apply_preset("Cube corners")
    first = view.sim.properties()
    assert "All three moments are equal" in " ".join(first["notes"])
    axes = [first["axes"]]
    for k in range(5):  # a drag: the mass moves a little each callback; the frame must not jump
        positions = view.sim.positions.copy()
        positions[0] += 1e-9 * (k + 1)
        view.sim.set_particles(view.sim.masses, positions)
        axes.append(view.sim.properties()["axes"])
    assert max(float(np.abs(a - axes[0]).max()) for a in axes) < 1e-6


def test_masses_are_added_weighed_moved_and_bad_values_refused(manual) -> None:
    view = _inertia(manual)
    client = manual.client
    n = len(view.sim.masses)
    view.gui_add_remove.value = "Add mass"
    assert len(view.sim.masses) == n + 1 and view.selected == n
    client.set_value(view.gui_mass, 4.0)
    manual.wait(lambda: view.sim.masses[n] == 4.0)
    client.set_value(view.gui_position, (0.5, 1.0, -0.5))
    manual.wait(lambda: tuple(view.sim.positions[n]) == (0.5, 1.0, -0.5))
    radius = float(np.asarray(view._balls[n].scale).ravel()[0])
    assert radius == pytest.approx(inertia_scene.BALL_RADIUS * 4.0 ** (1 / 3))
    client.set_value(view.gui_mass, -1.0)
    manual.wait(lambda: "refused" in view.message.text)
    assert view.sim.masses[n] == 4.0
    client.set_value(view.gui_position, (99.0, 0.0, 0.0))
    manual.wait(lambda: "x = " in view.message.text)
    assert tuple(view.sim.positions[n]) == (0.5, 1.0, -0.5)
    view.gizmo.position = (0.25, 0.25, 0.25)  # the gizmo, dragged (its callback from the server side)
    view._dragged()
    np.testing.assert_allclose(view.sim.positions[n], (0.25, 0.25, 0.25))
    assert manual.session.error_count == 0, manual.session.last_error


def _stl(mesh: trimesh.Trimesh) -> bytes:
    out = io.BytesIO()
    mesh.export(out, file_type="stl")
    return out.getvalue()


def _upload(view, name: str, content: bytes) -> None:  # type: ignore[no-untyped-def]
    view.gui_upload = types.SimpleNamespace(value=types.SimpleNamespace(name=name, content=content))
    view._uploaded()


def test_a_box_mesh_matches_its_closed_form_and_bad_meshes_are_refused(manual, monkeypatch) -> None:
    view = _inertia(manual)
    view.gui_mesh_mass.value = 2.0
    _upload(view, "box.stl", _stl(trimesh.creation.box(extents=(0.6, 0.4, 0.2))))
    props = view.sim.properties()
    assert props["mass"] == pytest.approx(2.0)
    expected = np.sort(box_inertia(2.0, (0.6, 0.4, 0.2)))
    np.testing.assert_allclose(np.sort(props["moments"]), expected, rtol=1e-6)  # STL stores float32
    good = view.sim.mesh
    open_box = trimesh.creation.box()
    open_box = trimesh.Trimesh(open_box.vertices, open_box.faces[:-1], process=False)
    inside_out = trimesh.creation.box()
    inside_out = trimesh.Trimesh(inside_out.vertices, inside_out.faces[:, ::-1], process=False)
    cases = [("open.stl", _stl(open_box), "open"), ("inside.stl", _stl(inside_out), "inside"),
             ("junk.stl", b"not a mesh at all", "unreadable"), ("notes.txt", b"x", "not a mesh file"),
             ("huge.stl", b"\0" * (inertia_scene.MAX_UPLOAD_BYTES + 1), "larger than 20 MiB")]
    for name, content, reason in cases:
        _upload(view, name, content)
        assert "Mesh refused" in view.message.text and reason in view.message.text, (name, view.message.text)
        assert view.sim.mesh is good  # the last valid body stays
    monkeypatch.setattr(inertia_scene, "MAX_FACES", 100)
    _upload(view, "ball.stl", _stl(trimesh.creation.icosphere(subdivisions=2)))
    assert "320 faces, more than 100" in view.message.text and view.sim.mesh is good


def test_spin_it_hands_the_body_to_the_free_body_scene(manual) -> None:
    view = _inertia(manual)
    manual.session.apply_preset("Triangle")
    moments = view.sim.properties()["moments"]
    view.spin_it()
    free = manual.session.scene
    assert free.title == "Free body"
    np.testing.assert_allclose(free.sim.model.inertia, moments, rtol=1e-12)
    manual.session.select_scene("Inertia")
    view = manual.session.scene
    view.gui_mesh_mass.value = 1.0
    _upload(view, "box.stl", _stl(trimesh.creation.box(extents=(0.9, 0.5, 0.2))))
    view.spin_it()
    free = manual.session.scene
    assert free.sim.mesh is not None and "handed on from the Inertia scene" in free.gui_param_status.content
    expected = np.sort(box_inertia(1.0, (0.9, 0.5, 0.2)))
    np.testing.assert_allclose(free.sim.model.inertia, expected, rtol=1e-6)  # STL stores float32
    manual.session.apply_preset("Disc")  # a preset: the box gives way
    assert free.sim.mesh is None and manual.session.error_count == 0


def test_O_dragged_with_its_gizmo_and_a_mesh_given_by_its_density(manual) -> None:
    view = _inertia(manual)
    view.O_gizmo.position = (0.5, 0.5, -0.5)  # dragged (the callback from the server side)
    view._O_dragged()
    np.testing.assert_allclose(view.sim.properties()["O"], (0.5, 0.5, -0.5))
    assert "m(|d|²𝟙 − d dᵀ)" in view.readout.handle.content
    view.gui_mesh_given.value = "density [kg/m³]"
    view.gui_mesh_mass.value = 500.0
    _upload(view, "box.stl", _stl(trimesh.creation.box(extents=(1.0, 2.0, 3.0))))
    assert view.sim.properties()["mass"] == pytest.approx(3000.0, rel=1e-6)
    view.gui_mesh_mass.value = -1.0
    _upload(view, "box.stl", _stl(trimesh.creation.box()))
    assert "density -1.0: positive wanted" in view.message.text and view.sim.mesh_mass == pytest.approx(3000.0)
