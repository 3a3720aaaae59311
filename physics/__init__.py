"""Rigid-body mechanics after Overdijk's memo: pure NumPy/SciPy, no GUI imports.

Modules: `so3` (hat, vee, exp, log), `euler` (z-x-z angles, ω), `inertia`, `moving_frames`,
and the dynamics (`dynamics`, `integrators`, `exact_free`, `exact_top`).
"""
