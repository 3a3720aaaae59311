"""The Inertia scene's texts as pure functions (`app.scenes.inertia.readouts`), no server.

The properties come from `InertiaSystem` (no viser); the numbers read back from the texts are
checked against references independent of the scene's code: the tensor (3.5) written out here as
a sum over the particles, NumPy's eigenvalues, and the closed form of a uniform box's tensor.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
import trimesh

from app.scenes.inertia.readouts import key_numbers_of, readout_text, spin_text
from app.scenes.inertia.simulation import InertiaSystem
from tests.test_inertia_scene import readout_matrices as matrices
from tests.test_inertia_scene import tensor

READOUT_ATOL = 0.6e-4  # [kg m²] I_O of a ~1 kg m² body is printed to 4 decimals
MASSES = [1.0, 2.0, 0.5]
POSITIONS = [[0.5, 0.0, 0.0], [-0.2, 0.4, 0.1], [0.0, -0.3, 0.6]]


def point(text: str, name: str) -> np.ndarray:
    match = re.search(re.escape(name) + r" = \(([^)]*)\) m", text)
    assert match, (name, text)
    return np.array([float(v) for v in match.group(1).split(", ")])


def principal_moments(text: str) -> np.ndarray:
    match = re.search(r"I1 ≤ I2 ≤ I3 = ([^ ]+, [^ ]+, [^ ]+) kg m²", text)
    assert match, text
    return np.array([float(v) for v in match.group(1).split(", ")])


def test_particles_about_their_centre_of_mass() -> None:
    system = InertiaSystem(MASSES, POSITIONS)
    text = readout_text(system.properties(), 1.0, masses=3)
    com = np.average(POSITIONS, axis=0, weights=MASSES)
    I_cm = tensor(MASSES, POSITIONS, com)
    assert text.startswith("**3 point masses**, m = 3.5 kg")
    np.testing.assert_allclose(point(text, "centre of mass c"), com, atol=0.51e-4)
    assert " m = c" in text and "I_cm +" not in text and "drawn ×" not in text
    (I_O, axes) = matrices(text)
    np.testing.assert_allclose(I_O, I_cm, atol=READOUT_ATOL)
    moments = np.linalg.eigvalsh(I_cm)
    np.testing.assert_allclose(principal_moments(text), moments, rtol=0.6e-4)
    np.testing.assert_allclose(np.abs(axes.T @ I_cm @ axes), np.diag(moments), atol=1e-3)  # columns are principal
    assert np.linalg.det(axes) == pytest.approx(1.0, abs=1e-3)  # right-handed


def test_particles_about_another_point_show_the_parallel_axis_term() -> None:
    system = InertiaSystem(MASSES, POSITIONS)
    O = np.array([1.0, -0.5, 0.25])
    system.set_about(O)
    text = readout_text(system.properties(), 1.0, masses=3)
    com = np.average(POSITIONS, axis=0, weights=MASSES)
    d = com - O
    assert "**I_O = I_cm + m(|d|²𝟙 − d dᵀ)**, d = c − O" in text
    np.testing.assert_allclose(point(text, "O"), O, atol=0.51e-4)
    I_O, I_cm, term, _axes = matrices(text)
    np.testing.assert_allclose(I_O, tensor(MASSES, POSITIONS, O), atol=READOUT_ATOL)
    np.testing.assert_allclose(I_cm, tensor(MASSES, POSITIONS, com), atol=READOUT_ATOL)
    np.testing.assert_allclose(term, 3.5 * (d @ d * np.eye(3) - np.outer(d, d)), atol=READOUT_ATOL)
    np.testing.assert_allclose(principal_moments(text), np.linalg.eigvalsh(tensor(MASSES, POSITIONS, O)), rtol=0.6e-4)


def test_masses_on_a_line_say_so() -> None:
    system = InertiaSystem([1.0, 1.0], [[0.0, 0.0, -0.5], [0.0, 0.0, 0.5]])
    text = readout_text(system.properties(), 1.0, masses=2)
    np.testing.assert_allclose(principal_moments(text), [0.0, 0.5, 0.5], atol=1e-12)  # 2 × 1 kg × (0.5 m)²
    assert "A principal moment is **zero**" in text and "I2 = I3" in text


def test_a_mesh_drawn_at_a_scale() -> None:
    box = trimesh.creation.box(extents=(1.0, 2.0, 3.0))
    system = InertiaSystem([1.0], [[0.0, 0.0, 0.0]])
    system.set_mesh("box.stl", box.vertices, box.faces, mass=6.0)
    k = system.display_scale()
    text = readout_text(system.properties(), k, mesh_name="box.stl")
    assert text.startswith("a uniform solid **box.stl**, m = 6 kg")
    assert f"drawn ×{k:g} (its size is 3 m)" in text and k != 1.0
    a, b, c = 1.0, 2.0, 3.0
    closed_form = 6.0 / 12.0 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])  # 6.5, 5, 2.5
    np.testing.assert_allclose(principal_moments(text), np.sort(closed_form), rtol=1e-5)
    np.testing.assert_allclose(matrices(text)[0], np.diag(closed_form), atol=READOUT_ATOL)
    assert [n.words() for n in key_numbers_of(system.properties(), mesh_name="box.stl")] == [
        "box.stl: m = 6 kg", "principal moments about O = 2.5, 5, 6.5 kg m²"]


def test_key_numbers_and_the_spin_note() -> None:
    system = InertiaSystem(MASSES, POSITIONS)
    body, moments = (n.words() for n in key_numbers_of(system.properties(), masses=np.array(MASSES)))
    assert body == "masses [kg] = 1, 2, 0.5"
    shown = [float(v) for v in moments.removeprefix("principal moments about O = ").removesuffix(" kg m²").split(", ")]
    np.testing.assert_allclose(shown, np.linalg.eigvalsh(system.properties()["I_O"]), rtol=0.6e-3)
    assert spin_text("3 point masses", (0.5, 1.0, 1.2), 1.0) == (
        "Spun from the Inertia scene: 3 point masses, about its middle axis y′.")
    scaled = spin_text("top.stl", (8.0, 8.0, 9.0), 2.0 / 9.0)
    assert scaled.startswith("Spun from the Inertia scene: top.stl, about its middle axis y′. "
                             "Its moments (8, 8, 9 kg m²)")
    assert "are shown ×0.222 to fit the sliders" in scaled
