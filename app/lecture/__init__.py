"""The lecture: one presenter's room shown to the class, above the scene kit and below the
browser's roles (`app.roles`) and its panels (`app.hall`).

- `app.lecture.lectern`: the `Lectern`, one per app: who presents, the hall's state, the shared
  screen and its followers (its docstring lists who owns each piece of lecture state and what
  ends it).
- `app.lecture.follower`: a follower's read-only panel and its status (`FollowerStatus`, a typed
  value sent across processes as data, rendered by the panel).
- `app.lecture.caption`: the caption a projector and the followers read (lesson step, badge).
- `app.lecture.room_plot`: the presenter's plot copied to the followers.
- `app.lecture.gate`: the presenter lock across processes (one presenter; wrong codes limited
  over every browser and process together).
- `app.lecture.bus`: one lecture across processes (what followers on another process see, and
  `Explore on my own` there).

Imports go down only: nothing here imports `app.hall`, `app.roles`, `app.session` or `app.main`;
the Redis plumbing below it is `app.cluster`.
"""
