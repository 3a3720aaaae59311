"""The app on several processes: nginx in front, Redis between them (`--workers N`, `--redis URL`).

Without `--workers` the app is one process and imports nothing from here but what is inert
without Redis.  With it:

- `app.cluster.services`: the real parts as child processes (redis-server, nginx) on free local
  ports, found on PATH, each stopped with the app; a missing one is named with the command that
  installs it.
- `app.cluster.launch`: `--workers N` starts Redis (unless `--redis URL`), N app processes on
  free local ports and nginx on `--port` in front of them (websockets by least connections), and
  stops them all on Ctrl-C.
- `app.cluster.gate`: the presenter lock across processes (one presenter; wrong codes limited over
  all browsers and processes together).
- `app.cluster.bus`: one lecture across processes (what followers on another process see, and
  `Explore on my own` there).
"""
