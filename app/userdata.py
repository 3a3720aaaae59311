"""Where what a user saves goes: the app's data folder (never the package's own files).

`--data-dir PATH` names it; by default it is the platform's place for an application's data:
`$XDG_DATA_HOME/rigid-body-lab` (else `~/.local/share/rigid-body-lab`) on Linux,
`~/Library/Application Support/rigid-body-lab` on macOS, `%APPDATA%\\rigid-body-lab` on Windows.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

__all__ = ["APP_FOLDER", "default_data_dir", "ensure_data_dir"]

APP_FOLDER = "rigid-body-lab"


def default_data_dir() -> Path:
    """The platform's data folder for the app (not created)."""
    if sys.platform == "win32":
        return Path(os.environ.get("APPDATA") or Path.home() / "AppData" / "Roaming") / APP_FOLDER
    if sys.platform == "darwin":
        return Path.home() / "Library" / "Application Support" / APP_FOLDER
    return Path(os.environ.get("XDG_DATA_HOME") or Path.home() / ".local" / "share") / APP_FOLDER


def ensure_data_dir(path: Path | str | None = None) -> Path:
    """`path` (or the default) made if missing; ValueError with the reason if it cannot be."""
    folder = Path(path).expanduser() if path else default_data_dir()
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise ValueError(f"cannot use {folder} as the data folder: {error.strerror or error}") from error
    if not os.access(folder, os.W_OK):
        raise ValueError(f"cannot use {folder} as the data folder: not writable")
    return folder
