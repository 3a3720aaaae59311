"""The scene kit: what every scene of the lecture app is built from, in rooms that stack (a room
imports only rooms below it; `tests/test_layers.py` reads the imports):

- `core`: the room (one simulation, its transport, its views), the draw target, the replay
  history, presets, plot samples, traces, and the shared constants (`common`);
- `panel` (the browser's panel: transport, bound controls, plots, timeline) and `draw` (the 3D:
  widgets, lean poses, labels, screen projection), neither importing the other;
- `view`: `SceneView`, the base of every scene's view;
- `rigid`: what rigid-body scenes share (simulation, view, texts, ghost, hand, arrows, plots).

The recipe for a new scene:

1. **A simulation** with no viser in it (`app.kit.core.room.Simulation`): the state, `advance(dt)`
   [s of simulated time], `reset()` back to its own initial conditions (never read from a
   widget), `t`, `version`, bumped whenever what is drawn changes, and `fork()`, an exact,
   independent copy (same state bit for bit, time, history, integrator state; a deep copy
   usually does, `tests/test_fork.py` checks every scene).  It may keep plot samples
   (`take_sample()`, called by the room at 10 Hz of wall time into an
   `app.kit.core.samples.SampleBuffer`) and traces of moving points (`app.kit.core.trace.Trace`, drawn
   by `app.kit.draw.widgets.TraceLines`): history lives in the simulation, never in a view, so a
   view built later (a late joiner, an explorer's fork) shows it.  A rigid body already has
   one: `app.kit.rigid.simulation.RigidBodySimulation` (`track` follows a point).  Physics formulas live
   in `physics/`, with tests.

2. **A view class** under `app/scenes/`, subclassing `app.kit.view.SceneView`: a small scene is
   one file; a big one is a package (`app/scenes/moving_frame/`, the template to copy): `simulation.py` (no viser:
   `tests/test_layers.py` checks it, through everything it imports), `readouts.py` (its texts
   as pure functions, numbers to strings, tested without viser as `tests/test_*_readouts.py`
   do), `view.py`, and an `__init__.py` that re-exports the names others import.
   The class is the scene: class attributes `title` (the dropdown option), `root` (the scene
   node everything hangs under), `view` (a `CameraView`), `preset_file` (and `param_specs`,
   `rate_specs` if its presets carry parameters or rates); classmethods
   `simulation_from_preset(preset)` (a new simulation at the preset's t = 0) and
   `start_preset(sim, preset)` (the preset's run started in the room's simulation, the same
   object), and `read_presets()` only if its preset file has fields of its own.  The base
   does the rest once for every scene: `presets()` (read once per scene), `preset(name)`,
   `new_simulation()` (at the first preset) and `apply_preset(room, name)`, whose rule is
   the same everywhere: **a preset starts paused at its t = 0** (the lecturer shows the
   initial condition, then presses Play).  An instance draws the room's simulation for one
   client: `__init__` sets its state and ends with `self.build()`, which calls `_build_scene`
   and `_build_gui` and joins the room; `frame(dt)` sends, per frame, only what changed since the last one and
   what is on screen; `refresh()` redraws everything after an edit.  Messages, errors, the
   camera, removal and quiet slider writes (`self.quiet`, no feedback) come from the base.
   A rigid-body scene subclasses `app.kit.rigid.view.RigidBodyView` instead and only fills in
   its parameters, rate sliders, shape and extras (`app/kit/rigid/torque_free.py`, ~150 lines, and the
   scenes `app/scenes/free_body.py` and `app/scenes/poinsot/` built on it).

   Build it from the shared pieces, never a copy of them:
   - panel (`app.kit.panel.gui`): `MessageLine` (refusals), `Transport` (Play / Pause, ▶| Step,
     ⟲ Reset, time scale, integrator, status; it calls the room), `PresetsRow`, `Tabs` (Setup /
     Readout / Plots; the server knows which is shown, so a closed tab costs nothing),
     `Readout` (sent only when its text changed), `add_slider` with `SliderSpec` (range
     checks and refusal messages), and `app.kit.panel.plots.LivePlots`;
   - 3D (`app.kit.draw.widgets`): `Stage` (grid, space axes), `Body` (a frame turned by
     R_space_body, its shape, its axes; instantiate it twice for a second body), `LineOfNodes`
     (with its gimbal-lock fade), `Vector` (an arrow and its label: ω, L), `TraceLines` (a
     simulation's trace, sent chunk by chunk);
   - `app.kit.core.common`: colours, lengths, `Throttle`, formatting, `gimbal_note`.
   - 3D labels: every label goes to the view's `self.labels` (`app.kit.draw.labels.LabelLayer`) with a
     priority (KEY, AXES, DETAIL; the widgets take `labels=`); who wants one shown calls
     `labels.want(label, visible)`, never `label.visible = ...`; `frame` ends with
     `self.labels.update(dt)` and `refresh` with `self.labels.settle()`, so no two labels overlap.

   - where it draws: `self.client` is a `DrawTarget` (`app.kit.core.target`); interactive handles
     (transform gizmos, clickable nodes) go into `self.controls` only, the scene of the one
     browser that controls the room, or None (a recording): never into `self.client.scene`,
     which may be the lecture hall's shared scene (the rule of `app.lecture.lectern`);
   - the panel's head: `self.build_head(intro, ...)` (intro, message line, transport); a scene
     whose simulation has `snapshot`/`restore` gets the replay's `Timeline` under it.

   Every callback goes through `wrap(where, fn)` (the session's guard: the room's lock, errors
   shown, never raised).  A control bound to a simulation value is one call,
   `self.bind(handle, where, apply, current, spec=...)` (`app.kit.panel.binding`): each value is applied
   when it arrives (the page sends typed numbers once, complete), refused with a message right under
   the control and the field put back to `current()` otherwise, and never written into while its user
   moves it.  A user's edit
   changes the room's simulation and calls `room.refresh()`, so every view of the room shows it.

3. **Presets** as data: `assets/presets/<scene>.json` (format in `app.kit.core.presets`), checked
   at start.

4. **One line** in `app/scenes/__init__.py` (`SCENES`), which builds the dropdown.  The test
   `tests/test_scene_kit.py` then builds the scene, applies every preset, plays, steps,
   resets and removes it.

5. **Its budgets and its fork**: an entry in `BUDGETS` of `tests/test_frame_budget.py` (the
   scene messages a playing frame may send, own room and follower, and whether it is within
   the byte budget), and a bit-exact `fork()` (item 1) with the scene's edit in `EDITS` of
   `tests/test_fork.py`, which checks that a fork draws and goes on exactly as the original
   (each table's test names the scene it lacks).

6. **What the room codec decodes** (`app.codec`: Explore across processes, Share) is derived
   from the scene (`app.scenes.simulation_parts`: the classes of its simulation class's module);
   only a function or class of another module that its simulation holds (a point a trace
   follows: `HeavyTopView.simulation_parts`) is declared, in `simulation_parts`.

The loop (`app.main.App.frame`, once per frame): every room advances once (`Room.advance`: its
simulation, if playing, whatever the number of views), then each view draws (`Room.draw`) if
its browser is ready for a frame (`app.backpressure.FramePacer`) and its wire is not busy, with
the wall time it owes since it last drew; then each wire sends its frame (`app.wire`).
`Room.tick` does both for one room (tests).
"""
