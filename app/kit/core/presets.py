"""Presets are data: one JSON file per scene under `assets/presets/`, read and checked at start.

The shipped files are read through `app.data` (importlib.resources: the checkout's `assets/`, or
`app/assets/` in an installed wheel); `PRESETS_DIR` is that folder.

A file is an object with a list `presets`; each preset is

    {"name": "Dzhanibekov", "group": "Presets",          # group: the button row it sits in
     "note": "what to watch (Markdown)",
     "params": {"I1": 0.3, "I2": 0.75, "I3": 1.0},        # the scene's body parameters
     "angles_deg": [-30, 60, 0],                          # z-x-z φ θ ψ [deg]
     "rates": {"w1": 0.05, "w2": 5.0, "w3": 0.05}}        # the scene's rate sliders

The keys of `params` and `rates` are the scene's slider keys (`SliderSpec.key`), each value in
the slider's range; a scene without parameters or rates leaves them out.  A lecturer adds a
preset by adding an entry: no code changes.  A broken file is refused as a whole with a
`PresetError` naming the file and the field (`presets[2].params.I3: 7 is outside [0.05, 5]`),
so the app does not start with a half-read lesson.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from importlib.resources.abc import Traversable
from pathlib import Path
from typing import Any

from app.data import presets_dir
from app.kit.core.common import SliderSpec

__all__ = ["PRESETS_DIR", "Preset", "PresetError", "load_presets", "preset_entries"]

PRESETS_DIR = presets_dir()  # the shipped presets (app.data: the checkout's or the installed ones)
ANGLE_RANGES_DEG = ((-180.0, 180.0), (0.0, 180.0), (-180.0, 180.0))


class PresetError(ValueError):
    """A preset file that cannot be used; the message names the file and the field."""


@dataclass(frozen=True)
class Preset:
    """A named initial condition of a scene.

    params: the body parameters in the scene's `param_specs` order; angles_deg: z-x-z
    (φ, θ, ψ) [deg]; rates: in the scene's `rate_specs` order and units; note: Markdown.
    """

    name: str
    group: str
    note: str
    params: tuple[float, ...]
    angles_deg: tuple[float, float, float]
    rates: tuple[float, ...]


def _number(value: Any, where: str, lo: float = -math.inf, hi: float = math.inf) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise PresetError(f"{where}: {value!r} is not a number")
    number = float(value)
    if not math.isfinite(number):
        raise PresetError(f"{where}: {value!r} is not finite")
    if not lo <= number <= hi:
        raise PresetError(f"{where}: {value!r} is outside [{lo:g}, {hi:g}]")
    return number


def _by_key(entry: dict[str, Any], field: str, specs: Sequence[SliderSpec], where: str) -> tuple[float, ...]:
    if not specs:
        if field in entry:
            raise PresetError(f"{where}.{field}: this scene has no {field}")
        return ()
    values = entry.get(field)
    if not isinstance(values, dict):
        raise PresetError(f"{where}.{field}: missing (an object with keys {', '.join(s.key for s in specs)})")
    unknown = sorted(set(values) - {spec.key for spec in specs})
    if unknown:
        raise PresetError(f"{where}.{field}: unknown key {unknown[0]!r} "
                          f"(the keys are {', '.join(s.key for s in specs)})")
    out = []
    for spec in specs:
        if spec.key not in values:
            raise PresetError(f"{where}.{field}.{spec.key}: missing")
        out.append(_number(values[spec.key], f"{where}.{field}.{spec.key}", spec.lo, spec.hi))
    return tuple(out)


def preset_entries(path: Path | Traversable) -> list[tuple[str, str, dict[str, Any]]]:
    """(place, name, entry) of each preset in a file: a JSON object whose `presets` is a non-empty
    list of objects with unique non-empty names; PresetError "file: presets[i].field: message".
    The scene's own fields are checked by its loader (`load_presets`, or a scene's own).
    path: a file, or a file in the installed data (`app.data`); the messages name it by str(path)."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise PresetError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise PresetError(f"{path}: not readable JSON: {error}") from None
    entries = data.get("presets") if isinstance(data, dict) else None
    if not isinstance(entries, list) or not entries:
        raise PresetError(f"{path}: presets: missing or empty (a list of presets)")
    out: list[tuple[str, str, dict[str, Any]]] = []
    for index, entry in enumerate(entries):
        where = f"presets[{index}]"
        if not isinstance(entry, dict):
            raise PresetError(f"{path}: {where}: not an object")
        name = entry.get("name")
        if not isinstance(name, str) or not name.strip():
            raise PresetError(f"{path}: {where}.name: missing or empty")
        if any(other == name for _, other, _ in out):
            raise PresetError(f"{path}: {where}.name: {name!r} appears twice")
        out.append((where, name, entry))
    return out


def load_presets(
    path: Path | Traversable,
    param_specs: Sequence[SliderSpec] = (),
    rate_specs: Sequence[SliderSpec] = (),
    check: Callable[[Preset], None] | None = None,
) -> tuple[Preset, ...]:
    """The presets of one scene's file, checked against its sliders; PresetError if broken.

    check: a scene's own test of a preset (e.g. that its moments make a body); it raises
    ValueError with a message, which is reported with the preset's place in the file.
    """
    presets: list[Preset] = []
    for where, name, entry in preset_entries(path):
        try:
            angles = entry.get("angles_deg")
            if not isinstance(angles, list) or len(angles) != 3:
                raise PresetError(f"{where}.angles_deg: missing (three numbers φ, θ, ψ in degrees)")
            angles_deg = tuple(_number(a, f"{where}.angles_deg[{k}]", *ANGLE_RANGES_DEG[k])
                               for k, a in enumerate(angles))
            preset = Preset(
                name=name,
                group=str(entry.get("group", "Presets")),
                note=str(entry.get("note", "")),
                params=_by_key(entry, "params", param_specs, where),
                angles_deg=(angles_deg[0], angles_deg[1], angles_deg[2]),
                rates=_by_key(entry, "rates", rate_specs, where),
            )
            if check is not None:
                try:
                    check(preset)
                except ValueError as error:
                    raise PresetError(f"{where} ({name}): {error}") from None
        except PresetError as error:
            raise PresetError(f"{path}: {error}") from None
        presets.append(preset)
    return tuple(presets)
