"""Everything a rigid-body scene shares: the simulation (`simulation`, no viser), its texts as pure
functions (`text`), the view every rigid scene subclasses (`view`, a `app.kit.view.SceneView`: its drawing; built on
`scene`, what a scene declares and its simulation from presets, and `panel`, its panel),
the torque-free scenes' view (`torque_free`), the exact ghost (`ghost`), the hand that kicks or
drags ω (`hand`), the generalized-force arrows (`lagrange_arrows`) and the energy plot
(`energy_plot`)."""
