"""The wheel's packages, found (the rest of the build is in pyproject.toml): every package under
app/ and physics/ (setuptools' find), and app.assets, the data folder assets/ installed under
that name (`package-dir` and `package-data` in pyproject.toml; read by app/data.py)."""

from setuptools import find_packages, setup

setup(packages=[*find_packages(include=["app", "app.*", "physics", "physics.*"]), "app.assets"])
