"""Tasks between lectures (issue 37): a question or a worksheet a student does in their own
room before a due time, judged by the physics, collected for the gradebook.

- `app.tasks.model`: `Task`, `Policy` (attempts, best or last), `Submission`, `verdict`, the
  gradebook's rows and CSV (no viser, no storage);
- `app.tasks.store`: the rules of a submission over a store (`SqliteTaskStore` in the data
  folder; `app.tasks.redis_store.RedisTaskStore` with `--workers`);
- `app.tasks.panel`: the student's `Task` folder and the lecturer's `Make a task` and table;
- `app.tasks.views`: the lecturer's 3D views of a question's answers (sphere of tips, gallery).
"""
