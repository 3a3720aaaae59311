"""The viser front end of rigid-body-lab: a thin layer over `physics` (no physics formulas here).

From the bottom up (`tests/test_layers.py` enforces the order):

- `app.viser_internals`: the one module that names viser's private attributes (checked at start,
  a feature turned off with a log line when one is missing); `app.wire` (a frame encoded once),
  `app.backpressure` (pacing), `app.data` (the packaged data files);
- `app.kit`: the scene kit, in rooms: `core` (room, draw target, history, presets, samples,
  traces), `panel` (transport, bound controls, plots, timeline), `draw` (3D widgets, lean poses,
  labels, screen projection), `view` (`SceneView`), `rigid` (the rigid body's simulation, view,
  texts and parts); its docstring is the recipe for a new scene;
- `app.scenes`: one module or package per scene, and the registry the Scene dropdown lists;
- `app.lessons`, `app.export`, `app.lecture.follower`, `app.lecture.lectern` (the lecture hall's lock),
  `app.hall` (projector layout, lesson runner, notes, lecture panel);
- `app.session` (one `Session` per browser), `app.main` (the server, its loop, the command line).
"""
