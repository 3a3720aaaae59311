"""Ask the class in the panels: the names of `app.hall.ask_presenter` (the presenter's `Ask the class`
folder), `app.hall.ask_student` (a student's question) and `app.hall.ask_kinds` (each kind's form
fields and widget), in one place.  What follows is what they do together.

**The presenter** (`AskPanel`, shown only while the browser presents): a form (kind, question,
options, the right option or the true direction; a lesson step with a question fills it in) and
`Ask the class`; then the round: the live count ("31 of 44 answered", `count_text`: the answers
against every browser following or exploring, on every process), for a choice a histogram in
the panel (`histogram_text`, bars of text; the round before it beside after `Vote again`), for a
direction every answer's tip as a point on one sphere of radius SPHERE_RADIUS around the origin
(the body's centre) in the presenter's own 3D view, the true direction an arrow once revealed.
`Close the round`, `Vote again`, `Reveal the answer`, `Download answers (CSV)` and `New
question`; once a round has ended (`New question`, or a presenter stopped or left: the round is
the presenter's, `app.ask.hub`), `Download earlier rounds (CSV)`.  Every CSV is saved by the
browser at once (`app.kit.panel.download.save_download`).  The sphere is drawn in the
presenter's own scene (`client.scene`), so the followers' screens never show the others' answers.

**A student** (`AnswerPanel`, every browser but the presenter's): while a round is open, the
question and its controls sit at the top of the panel and the follower's panel is folded away
until the student answers; a choice is one button per option, a direction is an arrow turned by
a gizmo (a laptop) or by two sliders, azimuth and elevation (a phone), then `Send my
direction`; a state is `Answer from my copy` (an exact copy of the presenter's room to work in,
`Explore`) then `Send my state`.  Answered, the panel says the answer and offers `Change my
answer` until the round closes.  The arrow and its gizmo are in the student's own scene: no
other browser sees or moves them.

Everything a student sends goes through `Student.answer` (the session: its anonymous token, the
app's `Rounds`), where the round's rules hold (`app.ask.round`): a refused answer is said in the
student's panel and changes nothing.  Both panels refresh from the app loop (`refresh`), writing
only what changed.
"""

from __future__ import annotations

from app.hall.ask_kinds import (
    DIRECTION_LABEL,
    FROM_COPY_LABEL,
    NUMBER_LABEL,
    PANELS,
    STATE_LABEL,
    Student,
    angles_of,
    direction_of,
    quaternion_to,
    rotated_z,
    target_of,
)
from app.hall.ask_presenter import (
    ASK_LABEL,
    CLOSE_LABEL,
    CSV_LABEL,
    EARLIER_LABEL,
    NEW_LABEL,
    REVEAL_LABEL,
    SPHERE_RADIUS,
    VOTE_AGAIN_LABEL,
    AskPanel,
    count_text,
    histogram_text,
    sphere_points,
)
from app.hall.ask_student import CHANGE_LABEL, AnswerPanel, answer_words

__all__ = ["ASK_LABEL", "CHANGE_LABEL", "CLOSE_LABEL", "CSV_LABEL", "DIRECTION_LABEL", "EARLIER_LABEL",
           "FROM_COPY_LABEL", "NEW_LABEL", "NUMBER_LABEL", "PANELS", "REVEAL_LABEL", "SPHERE_RADIUS", "STATE_LABEL",
           "VOTE_AGAIN_LABEL", "AnswerPanel", "AskPanel", "Student", "angles_of", "answer_words", "count_text",
           "direction_of", "histogram_text", "quaternion_to", "rotated_z", "sphere_points", "target_of"]
