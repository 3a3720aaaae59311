"""The viser front end of rigid-body-lab: a thin layer over `physics`.

`app.main` builds the server and its paced 60 Hz loop; `app.session` holds one `Session` per
connected browser (its own GUI, scene nodes and simulation) with a dropdown of the lecture
scenes: `app.explorer` (Euler angles and ω from the Euler rates), `app.free_body` (the
torque-free body) and `app.heavy_top` (the heavy symmetric top); the last two share
`app.simulation` (integration, drawing, readouts, live plots from `app.plots`, the playback
controls of `app.controls`).  No physics formulas live here: they come from `physics`.
Quaternions (wxyz) appear only where this package talks to viser (`app.common`).
"""
