"""The panel pieces written once: the transport, presets row, tabs, readouts and message line
(`gui`), a control bound to a simulation value (`binding`, with the page's typing guard), live
plots (`plots`) and the replay's timeline (`timeline`).  They import the core, never the 3D
drawing (`app.kit.draw`)."""
