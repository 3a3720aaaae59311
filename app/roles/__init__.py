"""A browser's roles, apart from its automation façade (`app.session.Session`).

One browser's session is a façade of thin delegations; what the browser does in each of its
roles is here, one module per role:

- `app.roles.showing`: what the browser shows now (`Showing`: its mode, the view, its own room,
  the switch lock) and what the roles need of the session (`Browser`).
- `app.roles.own_room`: its own room (`OwnRoom`, the explorer): the scene dropdown, the rooms
  and their views, presets (the scene's and the lecturer's own), keys and the palette's commands,
  the last lecture's room.
- `app.roles.following`: following the presenter and leaving to explore a copy (`Following`).
- `app.roles.presenting`: presenting (`Presenting`): taking and releasing the lock, calling
  everyone back, asking the class.
- `app.roles.student`: answering the class's question (`Student`).
- `app.roles.phone`: a narrow screen's folded panel and camera (`PhoneFit`).
- `app.roles.guard`: the session's guard (`Guard`) and its error line and load note (`ErrorLine`).

The roles are built by the session, in that order (a role is handed the roles it uses); each
reaches the session's panel parts (`app.hall`) through `Browser`, and never imports the session.
"""
