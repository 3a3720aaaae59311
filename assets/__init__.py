"""The app's data: presets/, lessons/ and meshes/ (no code).

In the repository this folder is `assets/`; the wheel installs it as the package `app.assets`
(pyproject.toml, `[tool.setuptools] package-dir`).  The app reads it through `app.data`.
"""
