"""The viser front end of rigid-body-lab: a thin layer over `physics`.

`app.main` builds the server and its 60 Hz loop, `app.session` holds one `Session` per
connected browser (its own GUI, scene nodes and, later, simulation), and `app.explorer` is
the z-x-z Euler-angle explorer scene.  No physics formulas live here: they come from
`physics`.  Quaternions (wxyz) appear only where this package talks to viser.
"""
