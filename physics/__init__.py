"""Rigid-body mechanics after Overdijk's memo: pure NumPy/SciPy, no GUI imports.

Conventions: docs/CONVENTIONS.md.  Modules: `so3` (hat, vee, exp, log), `quaternion` (wxyz),
`euler` (z-x-z angles, ω), `inertia`, `moving_frames`, and the dynamics: `dynamics` (Model,
State), `splitting`, `realtime` (RealtimeStepper), `dop853`, `scipy_peer`, `guards` (all
re-exported by `integrators`), `exact_free`, `exact_top`, `lagrange`, `methods`.
"""
