"""The panels of one browser's session (`app.session.Session`), one module per concern (a
following browser's panel is the lecture's, `app.lecture.follower`, below this):

- `app.hall.projector`: the projector layout (large text, a docked panel, large 3D labels).
- `app.hall.lesson_runner`: the Lesson folder and the running lesson's steps.
- `app.hall.notes`: the For the notes folder (Record, Screenshot).
- `app.hall.lecture_panel`: the live bar at the top of the panel (the presenter's badge, Stop
  presenting, Pointer, Call everyone back; an explorer's "Lecture on", Follow presenter, Stay)
  and the Lecture folder (Present, the presenter code, the pointer's label).
- `app.hall.narrow`: a narrow explorer's panel folded to one status line and `Details`.
- `app.hall.ask`: Ask the class, its names in one place: `app.hall.ask_presenter` the
  presenter's folder (the form, the live count, the kind's tally, the sphere of directions, a
  state round's gallery), `app.hall.ask_student` a student's question over the follower's
  panel, `app.hall.ask_kinds` each question kind's form fields and student widget (`PANELS`).
- `app.hall.share`: the Share folder (share codes of a room or a lesson).
- `app.hall.own_panel`: the Mine folder (the lecturer's own presets and lessons).

Each part builds its own widgets and wires its own callbacks through the session's guard; it is
handed what it acts on (callables, or the session through a small protocol), and never imports
the session.
"""
