"""The Inertia scene (memo §3).

References independent of the scene's code: the tensor written out here from (3.5), trimesh's
mass properties (`moment_inertia`, `moment_inertia_frame`, `principal_inertia_components`) for
meshes, box closed forms.  Checked: the tensor, principal frame and parallel-axis term, also as
read out in the panel; the cases of (3.8) said in words, a frame that does not flicker while a
mass is dragged through isotropic and symmetric configurations; meshes in each format uploaded
through the websocket as a browser does, and each bad kind refused with its reason while the
last valid body stays; "Spin it" (moments and mesh consistent); the preset file's errors.
"""

from __future__ import annotations

import io
import json
import re
import uuid
from pathlib import Path

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

import app.scenes.inertia as inertia_scene
import app.scenes.inertia.simulation as inertia_simulation
from app.kit.core.presets import PresetError
from physics.inertia import box_inertia, mesh_mass_properties, principal_axes_near

ATOL = 1e-12  # [kg m²] tensors of particles: the same sums in another order
READOUT_ATOL = 0.6e-4  # the panel prints 4 decimals


def tensor(masses, positions, about) -> np.ndarray:  # type: ignore[no-untyped-def]
    """Σ m (|x|² 𝟙 − x xᵀ), x from `about` (3.5), written out."""
    out = np.zeros((3, 3))
    for m, x in zip(masses, np.asarray(positions, dtype=float) - about):
        out += m * (float(x @ x) * np.eye(3) - np.outer(x, x))
    return out


def readout_matrices(content: str) -> list[np.ndarray]:
    """The 3×3 matrices printed in the readout, in order (rows '[ a  b  c ]')."""
    rows = [[float(v) for v in row.split()] for row in re.findall(r"^\[\s*(.*?)\s*\]$", content, re.M)]
    return [np.array(rows[k:k + 3]) for k in range(0, len(rows), 3)]


def _inertia(manual):  # type: ignore[no-untyped-def]
    manual.session.select_scene("Inertia")
    return manual.session.scene


def upload(manual, view, name: str, content: bytes) -> None:  # type: ignore[no-untyped-def]
    """Upload a file through the websocket as the browser's upload button does (viser's
    FileTransferStartUpload + FileTransferPart messages), then wait for the callback."""
    from viser import _messages

    before = view.sim.version, view.message.text
    transfer, part = str(uuid.uuid4()), 1 << 20
    parts = [content[k:k + part] for k in range(0, len(content), part)]
    source = view.mesh_panel.gui_upload._impl.uuid
    manual.client.send(_messages.FileTransferStartUpload(source, transfer, name, "application/octet-stream",
                                                         len(parts), len(content)))
    for index, chunk in enumerate(parts):
        manual.client.send(_messages.FileTransferPart(source, transfer, index, chunk))
    manual.wait(lambda: (view.sim.version, view.message.text) != before, timeout=30.0)


def exported(mesh: trimesh.Trimesh, kind: str) -> bytes:
    out = io.BytesIO()
    mesh.export(out, file_type=kind)
    return out.getvalue()


def asymmetric_mesh() -> trimesh.Trimesh:
    """A box turned about a skew axis and moved off the origin: products of inertia everywhere."""
    box = trimesh.creation.box(extents=(0.8, 0.5, 0.2))
    T = np.eye(4)
    T[:3, :3] = Rotation.from_rotvec([0.3, -0.5, 0.7]).as_matrix()
    T[:3, 3] = (0.4, -0.3, 0.2)
    box.apply_transform(T)
    return box


# ---------------------------------------------------------------------------------------- particles
def test_tensor_principal_frame_and_parallel_axis_term_also_as_read_out(manual) -> None:
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
    np.testing.assert_allclose(moments, np.linalg.eigvalsh(props["I_O"]), atol=1e-12)
    shown = readout_matrices(view.readout.handle.content)
    np.testing.assert_allclose(shown[0], props["I_O"], atol=READOUT_ATOL)
    np.testing.assert_allclose(np.abs(shown[-1]), np.abs(axes), atol=READOUT_ATOL)
    np.testing.assert_allclose(view.O_frame.wxyz, Rotation.from_matrix(axes).as_quat(scalar_first=True) *
                               np.sign(Rotation.from_matrix(axes).as_quat(scalar_first=True)[0]), atol=1e-9)

    view.gui_about.value = (1.0, -0.5, 0.25)  # O leaves the centre of mass
    props = sim.properties()
    O = np.array([1.0, -0.5, 0.25])
    I_O = tensor(sim.masses, sim.positions, O)
    np.testing.assert_allclose(props["I_O"], I_O, atol=ATOL)
    d = com - O
    term = 4.0 * (d @ d * np.eye(3) - np.outer(d, d))  # m = 4 kg
    np.testing.assert_allclose(props["parallel"], term, atol=ATOL)
    content = view.readout.handle.content
    assert "I_O = I_cm + m(|d|²𝟙 − d dᵀ)" in content
    I_O_shown, I_cm_shown, term_shown = readout_matrices(content)[:3]
    np.testing.assert_allclose(I_O_shown, I_O, atol=READOUT_ATOL)
    np.testing.assert_allclose(I_cm_shown, tensor(sim.masses, sim.positions, com), atol=READOUT_ATOL)
    np.testing.assert_allclose(term_shown, term, atol=READOUT_ATOL)
    np.testing.assert_allclose(np.asarray(view.O_frame.position), O, atol=1e-12)
    np.testing.assert_allclose(np.asarray(view.O_gizmo.position), O, atol=1e-12)
    view.gui_O_at_com.value = True  # a button press from the server side does not click; use the call
    view._set_about(None)
    assert "I_cm +" not in view.readout.handle.content


def test_the_cases_of_3_8_are_said_and_drawn(manual) -> None:
    view = _inertia(manual)
    manual.session.apply_preset("On a line")
    props = view.sim.properties()
    assert props["zero"][0] and "one line through O" in " ".join(props["notes"])
    semi = np.asarray(view._ellipsoid.scale)
    assert semi[0] == pytest.approx(inertia_scene.ELLIPSOID_SIZE)  # the endless axis, drawn cut ...
    assert semi[0] / semi[1] == pytest.approx(inertia_scene.ELLIPSOID_CUT)  # ... at the cut length
    view.gui_about.value = (0.0, 1.0, 0.0)  # O off the line: no zero moment any more
    assert not any(view.sim.properties()["zero"]) and "zero" not in view.readout.handle.content
    manual.session.apply_preset("Dumbbell")
    assert "Two moments are equal" in view.readout.handle.content and "zero" in view.readout.handle.content
    manual.session.apply_preset("Triangle")
    props = view.sim.properties()
    assert props["equal"] == [[0, 1]] and "(I1 = I2)" in view.readout.handle.content
    np.testing.assert_allclose(props["moments"], [1.5, 1.5, 3.0], atol=1e-12)  # m r²/2 twice, m r² (r = 1)
    for preset in ("Cube corners", "Tetrahedron"):
        manual.session.apply_preset(preset)
        props = view.sim.properties()
        assert "All three moments are equal" in view.readout.handle.content, preset
        np.testing.assert_allclose(np.asarray(view._ellipsoid.scale), inertia_scene.ELLIPSOID_SIZE)  # a sphere
    view.gui_add_remove.value = "Remove mass"
    while len(view.sim.masses) > 1:
        view.gui_add_remove.value = "Remove mass"
    assert "I_O = 0" in view.readout.handle.content and not view._ellipsoid.visible  # one mass, at O
    assert manual.session.error_count == 0, manual.session.last_error


@pytest.mark.parametrize(("preset", "step"), [("Cube corners", 2e-4), ("Tetrahedron", 2e-4), ("Triangle", 2e-4)])
def test_the_frame_does_not_flicker_while_a_mass_is_dragged(manual, preset: str, step: float) -> None:
    """A drag through a degenerate configuration: the mass moves away from it and back in small
    gizmo steps.  Where the moments are equal the axes are not determined; the frame drawn must
    not jump between the gizmo's callbacks there (and stays an eigenbasis, right-handed)."""
    view = _inertia(manual)
    manual.session.apply_preset(preset)
    start = view.sim.positions[0].copy()
    path = [start + step * s * np.array([1.0, 0.3, 0.0]) for s in (*range(0, 4), *range(4, -1, -1))]
    drawn = []
    for point in path:
        view.gizmo.position = tuple(point)  # the gizmo dragged (its callback from the server side)
        view._dragged()
        props = view.sim.properties()
        axes = props["axes"]
        assert np.linalg.det(axes) == pytest.approx(1.0, abs=1e-12)
        np.testing.assert_allclose(axes.T @ props["I_O"] @ axes, np.diag(props["moments"]), atol=1e-9)
        drawn.append(Rotation.from_quat(np.asarray(view.O_frame.wxyz), scalar_first=True).as_matrix())
    degenerate = [k for k, point in enumerate(path) if np.allclose(point, start)]
    assert len(degenerate) == 2  # the start and the return
    # Where the axes are determined (I1 < I2 < I3 by 1e-4) they turn with the body; where they are
    # not, the frame stays the last one drawn: no jump back at the degenerate point.
    np.testing.assert_allclose(drawn[-1], drawn[-2], atol=1e-9)
    # Off the degenerate point the perturbation fixes the axes: the same at every step (signs kept).
    for frame in drawn[2:-1]:
        np.testing.assert_allclose(frame, drawn[1], atol=1e-3)


def test_principal_axes_near_picks_the_eigenbasis_closest_to_the_last_one() -> None:
    rng = np.random.default_rng(7)
    for moments in ([1.0, 1.0, 2.0], [1.0, 3.0, 3.0], [2.0, 2.0, 2.0], [1.0, 2.0, 3.0]):
        R = Rotation.random(random_state=rng).as_matrix()
        I = R @ np.diag(moments) @ R.T
        previous = Rotation.random(random_state=rng).as_matrix()
        found, axes, equal = principal_axes_near(I, previous)
        np.testing.assert_allclose(found, moments, atol=1e-12)
        assert np.linalg.det(axes) == pytest.approx(1.0, abs=1e-12)
        np.testing.assert_allclose(axes.T @ I @ axes, np.diag(moments), atol=1e-12)
        # No other eigenbasis is closer to `previous`: compare with turns inside the eigenspaces.
        distance = np.linalg.norm(axes - previous)
        for angle in np.linspace(-np.pi, np.pi, 73):
            for group in equal:
                turn = np.eye(3)
                a, b = group[0], group[1]
                turn[np.ix_([a, b], [a, b])] = [[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]]
                other = axes @ turn
                assert np.linalg.norm(other - previous) >= distance - 1e-12
        if len(equal) == 0:
            np.testing.assert_allclose(np.abs(axes), np.abs(R), atol=1e-9)  # determined, up to signs
        if equal == [[0, 1, 2]]:
            np.testing.assert_allclose(axes, previous, atol=1e-12)  # isotropic: the last frame itself


def test_masses_are_added_weighed_moved_selected_and_bad_values_refused(manual) -> None:
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
    assert radius == pytest.approx(inertia_scene.BALL_RADIUS * 4.0 ** (1 / 3))  # volume ∝ m
    before = view.sim.positions.copy(), view.sim.masses.copy()
    for handle, value, said in ((view.gui_mass, -1.0, "refused"), (view.gui_mass, float("nan"), "refused"),
                                (view.gui_position, (99.0, 0.0, 0.0), "x = "),
                                (view.gui_position, (float("inf"), 0.0, 0.0), "x = "),
                                (view.gui_selected, "42", "No mass")):
        view.message.clear()
        client.set_value(handle, value)
        manual.wait(lambda said=said: said in view.message.text)
        np.testing.assert_array_equal(view.sim.positions, before[0])
        np.testing.assert_array_equal(view.sim.masses, before[1])
    view.gizmo.position = (0.25, 0.25, 0.25)  # the gizmo, dragged (its callback from the server side)
    view._dragged()
    np.testing.assert_allclose(view.sim.positions[n], (0.25, 0.25, 0.25))
    view.gizmo.position = (float("nan"), 0.0, 0.0)
    view._dragged()
    assert "not a point" in view.message.text
    np.testing.assert_allclose(view.sim.positions[n], (0.25, 0.25, 0.25))
    view._balls[0].on_click  # noqa: B018 - the balls are clickable
    view._select(1)  # what a click on the first ball does
    assert view.selected == 0 and view.gui_selected.value == "1"
    np.testing.assert_allclose(view.gizmo.position, view.sim.positions[0])
    view.gui_add_remove.value = "Remove mass"
    assert len(view.sim.masses) == n
    assert manual.session.error_count == 0, manual.session.last_error


# ---------------------------------------------------------------------------------------- meshes
@pytest.mark.parametrize("kind", ["stl", "obj", "ply", "off", "glb"])
def test_a_mesh_in_each_format_matches_trimesh_and_its_parallel_axis_term(manual, kind: str) -> None:
    view = _inertia(manual)
    view.mesh_panel.gui_amount.value = 2.0
    mesh = asymmetric_mesh()
    upload(manual, view, f"body.{kind}", exported(mesh, kind))
    assert view.sim.mesh is not None, view.message.text
    props = view.sim.properties()
    reference = mesh.copy()
    reference.density = 2.0 / reference.volume
    rtol = 1e-6  # the files keep ~7-8 significant digits of a vertex (float32, or text)
    scale = float(np.abs(reference.moment_inertia).max())
    assert props["mass"] == pytest.approx(2.0, rel=1e-12)
    np.testing.assert_allclose(props["com"], reference.center_mass, atol=rtol)
    np.testing.assert_allclose(props["I_cm"], reference.moment_inertia, atol=rtol * scale)
    np.testing.assert_allclose(props["moments"], reference.principal_inertia_components, rtol=rtol)
    for k in range(3):  # trimesh's principal vectors are rows, up to sign
        assert abs(float(props["axes"][:, k] @ reference.principal_inertia_vectors[k])) == pytest.approx(1.0, abs=1e-6)
    O = np.array([0.5, 0.5, -0.5])
    view._set_about(O)
    frame = np.eye(4)
    frame[:3, 3] = O
    np.testing.assert_allclose(view.sim.properties()["I_O"], reference.moment_inertia_frame(frame),
                               atol=rtol * 10 * scale)
    assert view.gizmo.visible is False and view.folder_masses.visible is False
    assert manual.session.error_count == 0, manual.session.last_error


def test_each_bad_mesh_is_refused_with_its_reason_and_the_last_body_stays(manual, monkeypatch) -> None:
    view = _inertia(manual)
    view.mesh_panel.gui_amount.value = 2.0
    upload(manual, view, "box.stl", exported(trimesh.creation.box(extents=(0.6, 0.4, 0.2)), "stl"))
    props = view.sim.properties()
    assert props["mass"] == pytest.approx(2.0)
    np.testing.assert_allclose(props["moments"], np.sort(box_inertia(2.0, (0.6, 0.4, 0.2))), rtol=1e-6)
    good = view.sim.mesh
    box = trimesh.creation.box()
    open_box = trimesh.Trimesh(box.vertices, box.faces[:-1], process=False)
    inside_out = trimesh.Trimesh(box.vertices, box.faces[:, ::-1], process=False)
    cases = [("open.stl", exported(open_box, "stl"), "open mesh"),
             ("open.obj", exported(open_box, "obj"), "open mesh"),
             ("inside.ply", exported(inside_out, "ply"), "inside out"),
             ("junk.stl", b"solid junk\nfacet nonsense\n", "unreadable"),
             ("junk.glb", b"glTF not really", "unreadable"),
             ("notes.txt", b"x", "not a mesh file"),
             ("huge.stl", b"\0" * (inertia_scene.MAX_UPLOAD_BYTES + 1), "larger than 20 MiB")]
    for name, content, reason in cases:
        upload(manual, view, name, content)
        assert "Mesh refused" in view.message.text and reason in view.message.text, (name, view.message.text)
        assert name in view.message.text and "last valid body stays" in view.message.text
        assert view.sim.mesh is good  # the last valid body stays
    monkeypatch.setattr(inertia_simulation, "MAX_FACES", 100)  # 500k faces would be a 25 MB upload
    upload(manual, view, "ball.stl", exported(trimesh.creation.icosphere(subdivisions=2), "stl"))
    assert "320 faces, more than 100" in view.message.text and view.sim.mesh is good
    assert manual.session.error_count == 0, manual.session.last_error


def test_a_mesh_given_by_its_density_and_reweighed(manual) -> None:
    view = _inertia(manual)
    view.mesh_panel.gui_given.value = "density [kg/m³]"
    assert view.mesh_panel.gui_amount.label == "density [kg/m³]" and view.mesh_panel.gui_amount.value == 1000.0
    view.mesh_panel.gui_amount.value = 500.0
    upload(manual, view, "box.stl", exported(trimesh.creation.box(extents=(1.0, 2.0, 3.0)), "stl"))
    assert view.sim.properties()["mass"] == pytest.approx(3000.0, rel=1e-6)
    view.mesh_panel.gui_amount.value = -1.0
    assert "density -1.0 kg/m³: a number from 1 to 100000 wanted" in view.message.text
    assert view.sim.mesh_mass == pytest.approx(3000.0) and view.mesh_panel.gui_amount.value == pytest.approx(500.0)
    view.mesh_panel.gui_amount.value = 1000.0  # re-weighed: I scales with the mass
    assert view.sim.properties()["mass"] == pytest.approx(6000.0, rel=1e-6)
    view.mesh_panel.gui_given.value = "mass [kg]"  # nothing changes, the box shows the mass
    assert view.mesh_panel.gui_amount.value == pytest.approx(6000.0) and view.sim.mesh_mass == pytest.approx(6000.0)
    view.mesh_panel.load_shipped("book")
    assert view.sim.mesh_name == "book.stl" and view.sim.mesh_mass == pytest.approx(6000.0)
    view.mesh_panel.load_shipped("../../etc/passwd")
    assert "No shipped mesh" in view.message.text and view.sim.mesh_name == "book.stl"


def test_O_is_dragged_with_its_own_gizmo(manual) -> None:
    view = _inertia(manual)
    view.O_gizmo.position = (0.5, 0.5, -0.5)  # dragged (the callback from the server side)
    view._O_dragged()
    np.testing.assert_allclose(view.sim.properties()["O"], (0.5, 0.5, -0.5))
    np.testing.assert_allclose(view.gui_about.value, (0.5, 0.5, -0.5))
    assert "m(|d|²𝟙 − d dᵀ)" in view.readout.handle.content
    view.mesh_panel.load_shipped("book")  # a mesh drawn ×k: the gizmo is in scene units, O in metres
    k = view.sim.display_scale()
    assert k > 1.0 and f"drawn ×{k:g}" in view.readout.handle.content
    view.O_gizmo.position = (0.1 * k, 0.0, 0.0)
    view._O_dragged()
    np.testing.assert_allclose(view.sim.properties()["O"], (0.1, 0.0, 0.0), atol=1e-12)


# ---------------------------------------------------------------------------------------- Spin it
def test_spin_it_hands_the_body_to_the_free_body_scene(manual) -> None:
    view = _inertia(manual)
    manual.session.apply_preset("On a line")
    view.spin_it()  # no rigid body: a zero moment
    assert manual.session.scene is view and "Nothing to spin" in view.message.text
    manual.session.apply_preset("L-shape")
    moments = view.sim.properties()["moments"]
    view.spin_it()
    free = manual.session.scene
    assert free.title == "Free body"
    np.testing.assert_allclose(free.sim.model.inertia, moments, rtol=1e-12)  # within the sliders: as they are
    assert free.sim.mesh is None and "Spun from the Inertia scene" in free.message.text

    manual.session.select_scene("Inertia")
    view = manual.session.scene
    view.mesh_panel.gui_amount.value = 1.0
    mesh = asymmetric_mesh()
    upload(manual, view, "box.stl", exported(mesh, "stl"))
    view.spin_it()
    free = manual.session.scene
    assert free.sim.mesh is not None and "handed on from the Inertia scene" in free.gui_param_status.content
    expected = np.sort(box_inertia(1.0, (0.8, 0.5, 0.2)))  # 0.024 .. 0.073 kg m²: below the sliders
    k = 2.0 / expected[2]
    np.testing.assert_allclose(free.sim.model.inertia, k * expected, rtol=1e-6)  # STL stores float32
    assert f"×{k:.3g}" in free.message.text
    # The mesh handed on is in its principal frame: its own tensor is diagonal, ascending, ∝ the moments.
    vertices, faces = free.sim.mesh
    own = mesh_mass_properties(vertices, faces, density=1.0 / mesh.volume)
    np.testing.assert_allclose(own.center_of_mass, 0.0, atol=1e-6)
    np.testing.assert_allclose(own.inertia_cm, np.diag(expected), atol=1e-6 * expected[2])
    manual.session.apply_preset("Disc")  # a preset: the mesh gives way
    assert free.sim.mesh is None and manual.session.error_count == 0


def test_spin_it_after_a_mesh_and_then_a_preset_names_the_point_masses(manual) -> None:
    view = _inertia(manual)
    view.mesh_panel.gui_amount.value = 1.0
    upload(manual, view, "box.stl", exported(asymmetric_mesh(), "stl"))
    manual.session.apply_preset("L-shape")  # the mesh gives way to point masses
    assert view.sim.mesh is None and view.sim.mesh_name == ""
    view.spin_it()
    text = manual.session.scene.message.text
    assert "point masses" in text and "box.stl" not in text


# ---------------------------------------------------------------------------------------- presets
def test_the_presets_are_the_six_of_the_brief() -> None:
    names = [p.name for p in inertia_scene.InertiaView.presets()]
    assert names == ["Dumbbell", "Triangle", "Cube corners", "On a line", "L-shape", "Tetrahedron"]


@pytest.mark.parametrize(("entry", "said"), [
    ({"group": "x", "masses": [1], "positions": [[0, 0, 0]]}, "presets[1].name: missing"),
    ({"name": "A", "masses": [1], "positions": [[0, 0, 0]]}, "presets[1].name: 'A' appears twice"),
    ({"name": "B", "masses": [1, -2], "positions": [[0, 0, 0], [1, 0, 0]]}, "presets[1].masses[1]: -2 is outside"),
    ({"name": "B", "masses": [1, 2], "positions": [[0, 0, 0]]}, "presets[1].positions: 2 points"),
    ({"name": "B", "masses": [1], "positions": [[0, 9, 0]]}, "presets[1].positions[0][1]: 9 is outside"),
    ({"name": "B", "masses": "heavy", "positions": [[0, 0, 0]]}, "presets[1].masses"),
    ({"name": "B", "masses": [1], "positions": [[0, 0, 0]], "colour": 1}, "presets[1]: unknown key 'colour'"),
])
def test_a_broken_preset_file_names_the_file_and_the_field(tmp_path: Path, entry: dict, said: str) -> None:
    path = tmp_path / "inertia.json"
    path.write_text(json.dumps({"presets": [{"name": "A", "masses": [1], "positions": [[0, 0, 0]]}, entry]}),
                    encoding="utf-8")
    with pytest.raises(PresetError) as error:
        inertia_scene.load_inertia_presets(path)
    assert str(error.value).startswith(f"{path}: ") and said in str(error.value), str(error.value)
