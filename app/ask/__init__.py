"""Ask the class (issue 26): questions as data, rounds with their rules, tallies and CSV; no viser.

- `app.ask.questions`: the kinds `Choice`, `Direction`, `State`, `Number` (frozen, one class
  each behind `QuestionKind`: check, dict, tally, CSV row, words), registered in `KINDS`, and
  `question_from_dict`;
- `app.ask.judges`: `JUDGES`, the State questions' judges by name (on `physics.judging`), `Judged`;
- `app.ask.tally_text`: the shape of a tally the kinds read, a State's judged histogram;
- `app.ask.round`: `Round` (answers keyed by an anonymous per-browser token, one per browser,
  bounded in number and rate), `Tally`, `Round.csv()`, `Round.vote_again()`.

The presenter's and the students' panels are `app.hall.ask` (a kind's form fields and widget:
`app.hall.ask_kinds`); answers from other processes come
through `app.cluster.askbus`.
"""

from app.ask.hub import Rounds, Shown
from app.ask.judges import JUDGES, Judged
from app.ask.questions import KINDS, Choice, Direction, Number, Question, State, question_from_dict, question_to_dict
from app.ask.round import Answer, RateLimit, Refused, Round, Tally, new_token

__all__ = ["JUDGES", "KINDS", "Answer", "Choice", "Direction", "Judged", "Number", "Question", "RateLimit", "Refused",
           "Round", "Rounds", "Shown", "State", "Tally", "new_token", "question_from_dict", "question_to_dict"]
