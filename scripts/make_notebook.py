"""Write docs/lecture_notes.ipynb (the worked example: memo §1, the Dzhanibekov flip, a heavy
top's U_eff) without outputs; tests/test_notebook.py executes it.  Run after editing the cells."""

from __future__ import annotations

from pathlib import Path

import nbformat
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

CELLS = [
    new_markdown_cell(
        "# Rigid bodies in a notebook\n\n"
        "The physics package (`physics`) and the app's scenes (`app.notebook.show`) in lecture notes. "
        "Run it with `pip install -e \".[notebook]\"` and `jupyter lab docs/lecture_notes.ipynb`: while the "
        "kernel runs, each scene below is live, with its panel (Play, sliders, plots). Rendered without a "
        "kernel (`jupyter nbconvert --to html`, Jupyter Book) each scene is a recorded player of the same "
        "motion that plays from the file.\n\n"
        "Conventions: `R = R_space_body`, z-x-z Euler angles φ, θ, ψ, radians in `physics`, SI units."),
    new_code_cell(
        "import numpy as np\n\n"
        "from app import notebook\n"
        "from physics.euler import matrix_from_euler_zxz, omega_body_from_euler_rates\n"
        "from physics.exact_free import FreeBodyExact\n"
        "from physics.so3 import exp_so3, single_rotation\n"
        "from physics.top_energy import energy_picture"),
    new_markdown_cell(
        "## §1 One rotation is one turn\n\n"
        "Any attitude D = Rz(φ) Rx(θ) Rz(ψ) is a single turn by Φ about an axis d: D = exp(Φ hat(d)) "
        "(memo (1.1)–(1.3))."),
    new_code_cell(
        "D = matrix_from_euler_zxz(*np.radians([30.0, 50.0, 20.0]))\n"
        "turn = single_rotation(D)\n"
        "print('d =', np.round(turn.axis, 6), ' Φ =', round(np.degrees(turn.angle), 6), '°')\n"
        "print('|exp(Φ hat(d)) − D| =', np.abs(exp_so3(turn.rotvec) - D).max())\n"
        "assert np.allclose(exp_so3(turn.rotvec), D, atol=1e-14)"),
    new_markdown_cell(
        "## The Dzhanibekov flip and its exact period\n\n"
        "A book spun about its intermediate axis y′ flips over and back. The exact solution (Jacobi "
        "elliptic functions) gives the period of ω_b(t); ω_y′ changes sign twice in it, so the body flips "
        "every half period, 2K(m)/λ. Below: the prediction, checked against the sign changes of the exact "
        "ω_y′(t), and the app's Free body scene in the same preset."),
    new_code_cell(
        "inertia = np.array([0.3, 0.75, 1.0])              # [kg m²], the preset Dzhanibekov\n"
        "R0 = matrix_from_euler_zxz(*np.radians([-30.0, 60.0, 0.0]))\n"
        "omega0_body = np.array([0.05, 5.0, 0.05])         # [rad/s]\n"
        "book = FreeBodyExact(inertia, R0, omega0_body)\n"
        "flip = book.omega_period / 2\n"
        "t = np.linspace(0.0, 3 * book.omega_period, 200_001)\n"
        "w_y = book.omega_body(t)[:, 1]\n"
        "changes = t[1:][np.sign(w_y[1:]) != np.sign(w_y[:-1])]\n"
        "print(f'm = {book.m:.6f}; a flip every {flip:.6f} s')\n"
        "print(f'sign changes of ω_y′ {np.diff(changes).round(4)} s apart')\n"
        "assert np.allclose(np.diff(changes), flip, atol=1e-3)"),
    new_code_cell('notebook.show("Free body", preset="Dzhanibekov", seconds=6)'),
    new_markdown_cell(
        "## A heavy top's effective potential\n\n"
        "With p_φ = L·e_z and p_ψ = I3 ω_z′ conserved, E = ½ I1 θ̇² + U_eff(θ): θ nods between the turning "
        "points θ₁, θ₂ where U_eff = E. The preset Loop (started with dφ/dt against the precession):"),
    new_code_cell(
        "I1, I3, mgl = 1.0, 0.5, 6.0                          # [kg m²], [kg m²], [N m]\n"
        "angles = np.radians([0.0, 60.0, 0.0])\n"
        "phi_dot, theta_dot, spin = np.radians(-31.541914317185263), 0.0, 12.0\n"
        "psi_dot = spin - phi_dot * np.cos(angles[1])       # ω_z′ = φ̇ cos θ + ψ̇\n"
        "omega_body = omega_body_from_euler_rates(angles, np.array([phi_dot, theta_dot, psi_dot]))\n"
        "top = energy_picture(I1, I3, mgl, matrix_from_euler_zxz(*angles), omega_body)\n"
        "theta = np.radians(np.linspace(20.0, 120.0, 11))\n"
        "for th, u in zip(np.degrees(theta), top.U_eff(theta)):\n"
        "    print(f'θ = {th:5.1f}°  U_eff = {u:8.3f} J' + ('   ≤ E' if u <= top.energy + 1e-9 else ''))\n"
        "print(f'E = {top.energy:.3f} J; θ₁ = {np.degrees(top.theta_1):.3f}°, θ₂ = {np.degrees(top.theta_2):.3f}°; '\n"
        "      f'{top.motion}: {top.description}')"),
    new_code_cell('notebook.show("Heavy top", preset="Loop", seconds=5)'),
]


def main() -> None:
    notebook = new_notebook(cells=CELLS, metadata={
        "kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"},
        "language_info": {"name": "python"}})
    path = Path(__file__).resolve().parents[1] / "docs" / "lecture_notes.ipynb"
    nbformat.write(notebook, path)
    print(path)


if __name__ == "__main__":
    main()
