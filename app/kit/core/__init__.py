"""The kit's core, below everything that draws or shows a panel: the room (`room`: one simulation,
its transport, the views watching it), where a view draws (`target`), the replay history
(`history`), presets as data (`presets`), plot samples (`samples`), traces of moving points
(`trace`), and the shared constants, specs and formatting (`common`).  Only the draw target
imports viser (it wraps a browser's client); the rest is plain Python and NumPy."""
