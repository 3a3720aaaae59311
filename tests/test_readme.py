"""The README's first commands are the ones CI runs."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _readme_commands() -> list[str]:
    return re.findall(r"```bash\n(.+?)\n```", (ROOT / "README.md").read_text())


def test_readme_starts_with_the_app_and_test_commands():
    app_command, test_command = _readme_commands()[:2]
    assert app_command.endswith("python -m app")
    assert "pytest" in test_command and '".[test]"' in test_command


def test_ci_runs_the_readme_test_command_verbatim():
    test_command = _readme_commands()[1]
    ci_lines = (ROOT / ".ci" / "run").read_text().splitlines()
    assert test_command in ci_lines


def test_ci_runs_ruff_and_mypy_before_the_tests():
    ci = (ROOT / ".ci" / "run").read_text()
    assert "ruff check ." in ci and "mypy physics app" in ci
    assert ci.index("mypy physics app") < ci.index(_readme_commands()[1])


def test_every_document_cited_exists():
    """Docstrings and docs cite sheets by name (docs/CONVENTIONS.md, CASEFILE.md, ...): each exists."""
    cited = set()
    for path in [*ROOT.glob("*.md"), *ROOT.glob("docs/*.md"), *ROOT.glob("*/**/*.py")]:
        if ".venv" in path.parts:
            continue
        cited |= set(re.findall(r"\b((?:docs/)?[A-Z][A-Z_]+\.md)\b", path.read_text(encoding="utf-8")))
    assert cited, "no citations found"
    missing = sorted(name for name in cited
                     if not (ROOT / name).exists() and not (ROOT / "docs" / name).exists())
    assert missing == []
