"""The wheel's packages, found (the rest of the build is in pyproject.toml): every package under
app/ and physics/ (setuptools' find), and app.assets, the data folder assets/ installed under
that name (`package-dir` and `package-data` in pyproject.toml; read by app/data.py).

The build also compiles the translation catalogs (`build_py` below): every
app/locale/<lang>/LC_MESSAGES/messages.po becomes messages.mo in the wheel (with Babel, a build
requirement in pyproject.toml), read by `app.i18n` through importlib.resources.  The .po files
stay in the repository; a checkout compiles them in memory (`app.i18n.catalog_bytes`)."""

import io
from pathlib import Path

from setuptools import find_packages, setup
from setuptools.command.build_py import build_py

LOCALE = Path(__file__).resolve().parent / "app" / "locale"


def compiled(po: Path) -> bytes:
    """The .mo bytes of the catalog `po` (fuzzy entries left out)."""
    from babel.messages.mofile import write_mo
    from babel.messages.pofile import read_po

    with po.open("rb") as handle:
        catalog = read_po(handle, locale=po.parent.parent.name)
    out = io.BytesIO()
    write_mo(out, catalog, use_fuzzy=False)
    return out.getvalue()


class BuildWithCatalogs(build_py):
    """setuptools' build_py, then every catalog compiled into the build (app/locale/<lang>/LC_MESSAGES/messages.mo)."""

    def run(self) -> None:
        super().run()
        for po in sorted(LOCALE.glob("*/LC_MESSAGES/messages.po")):
            target = Path(self.build_lib) / po.relative_to(LOCALE.parent.parent).with_suffix(".mo")
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(compiled(po))


setup(packages=[*find_packages(include=["app", "app.*", "physics", "physics.*"]), "app.assets"],
      cmdclass={"build_py": BuildWithCatalogs})
