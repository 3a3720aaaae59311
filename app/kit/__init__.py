"""The scene kit: what every scene of the lecture app is built from.  The recipe for a new scene:

1. **A simulation** with no viser in it (`app.kit.room.Simulation`): the state, `advance(dt)`
   [s of simulated time], `reset()` back to its own initial conditions (never read from a
   widget), `t`, `version`, bumped whenever what is drawn changes, and `fork()`, an exact,
   independent copy (same state bit for bit, time, history, integrator state; a deep copy
   usually does, `tests/test_fork.py` checks every scene).  It may keep plot samples
   (`take_sample()`, called by the room at 10 Hz of wall time into an
   `app.kit.samples.SampleBuffer`) and traces of moving points (`app.kit.trace.Trace`, drawn
   by `app.kit.widgets.TraceLines`): history lives in the simulation, never in a view, so a
   view built later (a late joiner, an explorer's fork) shows it.  A rigid body already has
   one: `app.kit.rigid.RigidBodySimulation` (`track` follows a point).  Physics formulas live
   in `physics/`, with tests.

2. **A view class** in one file under `app/scenes/`, subclassing `app.kit.view.SceneView`
   (a big scene is a package, `app/scenes/euler_angles/`: `simulation` and `readouts`, its
   texts as pure functions, import no viser (tests/test_layers.py), then `view` and its parts;
   its `__init__` re-exports the view).
   The class is the scene: class attributes `title` (the dropdown option), `root` (the scene
   node everything hangs under), `view` (a `CameraView`), `preset_file` (and `param_specs`,
   `rate_specs` if its presets carry parameters or rates); classmethods `new_simulation()`
   (at the first preset) and `apply_preset(room, name)` (`presets()` and `preset(name)` come
   from the base).  An instance draws the room's simulation for one client: `__init__` sets
   its state and ends with `self.build()`, which calls `_build_scene` and `_build_gui` and
   joins the room; `frame(dt)` sends, per frame, only what changed since the last one and
   what is on screen; `refresh()` redraws everything after an edit.  Messages, errors, the
   camera, removal and quiet slider writes (`self.quiet`, no feedback) come from the base.
   A rigid-body scene subclasses `app.kit.rigid_view.RigidBodyView` instead and only fills in
   its parameters, rate sliders, shape and extras (`app/kit/torque_free.py`, ~150 lines, and the
   scenes `app/scenes/free_body.py` and `app/scenes/poinsot.py` built on it).

   Build it from the shared pieces, never a copy of them:
   - panel (`app.kit.gui`): `MessageLine` (refusals), `Transport` (Play / Pause, ▶| Step,
     ⟲ Reset, time scale, integrator, status; it calls the room), `PresetsRow`, `Tabs` (Setup /
     Readout / Plots; the server knows which is shown, so a closed tab costs nothing),
     `Readout` (sent only when its text changed), `add_slider` with `SliderSpec` (range
     checks and refusal messages), and `app.kit.plots.LivePlots`;
   - 3D (`app.kit.widgets`): `Stage` (grid, space axes), `Body` (a frame turned by
     R_space_body, its shape, its axes; instantiate it twice for a second body), `LineOfNodes`
     (with its gimbal-lock fade), `Vector` (an arrow and its label: ω, L), `TraceLines` (a
     simulation's trace, sent chunk by chunk);
   - `app.kit.common`: colours, lengths, `Throttle`, formatting, `gimbal_note`.
   - 3D labels: every label goes to the view's `self.labels` (`app.kit.labels.LabelLayer`) with a
     priority (KEY, AXES, DETAIL; the widgets take `labels=`); who wants one shown calls
     `labels.want(label, visible)`, never `label.visible = ...`; `frame` ends with
     `self.labels.update(dt)` and `refresh` with `self.labels.settle()`, so no two labels overlap.

   - where it draws: `self.client` is a `DrawTarget` (`app.kit.target`); interactive handles
     (transform gizmos, clickable nodes) go into `self.controls` only, the scene of the one
     browser that controls the room, or None (a recording): never into `self.client.scene`,
     which may be the lecture hall's shared scene (the rule of `app.lectern`);
   - the panel's head: `self.build_head(intro, ...)` (intro, message line, transport); a scene
     whose simulation has `snapshot`/`restore` gets the replay's `Timeline` under it.

   Every callback goes through `wrap(where, fn)` (the session's guard: the room's lock, errors
   shown, never raised).  A control bound to a simulation value is one call,
   `self.bind(handle, where, apply, current, spec=...)` (`app.kit.binding`): each value is applied
   when it arrives (the page sends typed numbers once, complete), refused with a message and the
   field put back to `current()` otherwise, and never written into while its user moves it.  A user's edit
   changes the room's simulation and calls `room.refresh()`, so every view of the room shows it.

3. **Presets** as data: `assets/presets/<scene>.json` (format in `app.kit.presets`), checked
   at start.

4. **One line** in `app/scenes/__init__.py` (`SCENES`), which builds the dropdown.  The test
   `tests/test_scene_kit.py` then builds the scene, applies every preset, plays, steps,
   resets and removes it.

The loop (`app.main.App`) ticks each room once per frame: its simulation advances once, then
each of its views draws (`app.kit.room.Room.tick`).
"""
