"""The Inertia scene's texts as pure functions, from numbers to Markdown (no viser).

Each takes the system's properties (`InertiaSystem.properties()`: mass [kg], com, O, d [m],
I_O, I_cm, parallel [kg m²], principal moments ascending and axes as columns, the notes of
(3.8), the body's size [m]) and what the body is (a mesh's name, or the point masses [kg]).
The view puts them into the panel.  Tested without a browser in tests/test_inertia_readouts.py.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from app.i18n import DEFAULT_LANGUAGE, N_, Translator, translator
from app.kit.core.common import format_matrix
from app.kit.core.key_number import KeyNumber
from physics._types import Vec3

ENGLISH = translator(DEFAULT_LANGUAGE)

__all__ = ["key_numbers_of", "readout_text", "spin_text"]


def readout_text(props: Mapping[str, Any], display_scale: float, *, mesh_name: str | None = None,
                 masses: int = 0, tr: Translator = ENGLISH) -> str:
    """The readout: the body (the uniform solid `mesh_name`, or `masses` point masses) and its
    mass, c and O [m] (4 significant digits, rounding noise below 1e-12 of the body's size shown
    as 0), the display scale if it is not 1, I_O [kg m²] (~5 significant digits), I_cm plus the
    parallel-axis term if O is not c, the principal moments (5 digits) and axes (4 decimals), and
    the notes."""
    _ = tr.gettext
    O, d = props["O"], props["d"]
    mass = f"{props['mass']:.4g}"
    what = (_("a uniform solid **{name}**, m = {mass} kg").format(name=mesh_name, mass=mass) if mesh_name is not None
            else tr.ngettext("**{n} point mass**, m = {mass} kg", "**{n} point masses**, m = {mass} kg",
                             masses).format(n=masses, mass=mass))

    def point(x: Vec3) -> str:  # rounding noise (1e-17 of a 0.5 m body) shown as 0
        return ", ".join(f"{0.0 if abs(v) <= 1e-12 * max(props['size'], 1e-300) else v:.4g}" for v in x)

    lines = [what, _("centre of mass c = ({point}) m").format(point=point(props["com"])),
             f"O = ({point(O)}) m" + (" = c" if not np.any(d) else "")]
    if display_scale != 1.0:
        lines.append(_("drawn ×{scale} (its size is {size} m)").format(scale=f"{display_scale:g}",
                                                                      size=f"{props['size']:.3g}"))
    scale = float(np.abs(props["I_O"]).max())
    decimals = 4 if scale == 0.0 else min(12, max(4, 4 - math.floor(math.log10(scale))))  # ~5 digits
    text = "  \n".join(lines) + "\n\n**I_O** [kg m²]\n```\n" + format_matrix(props["I_O"], decimals) + "\n```\n"
    if np.any(d):
        text += ("**I_O = I_cm + m(|d|²𝟙 − d dᵀ)**, d = c − O:\n```\n" + format_matrix(props["I_cm"], decimals)
                 + "\n+\n" + format_matrix(props["parallel"], decimals) + "\n```\n")
    moments = props["moments"]
    text += (_("Principal moments I1 ≤ I2 ≤ I3 = {moments} kg m²").format(
        moments=", ".join(f"{m:.5g}" for m in moments)) + "  \n"
             + _("principal axes e1 e2 e3 (columns, right-handed)") + "\n```\n" + format_matrix(props["axes"], 4)
             + "\n```\n")
    for note in props["notes"]:
        text += _(note) + "  \n"
    return text


def key_numbers_of(props: Mapping[str, Any], *, mesh_name: str | None = None,
                   masses: Sequence[float] | np.ndarray = ()) -> list[KeyNumber]:
    """For the followers' panel: the body (the mesh `mesh_name` and its mass, or the point
    `masses` [kg]) and its principal moments about O [kg m²], each to 4 significant digits."""
    if mesh_name is not None:
        body = KeyNumber.made("m", (_significant(props["mass"]),), unit="kg", name=mesh_name)
    else:
        body = KeyNumber.made(N_("masses [kg]"), [_significant(m, 3) for m in masses])
    moments = [_significant(m) for m in props["moments"]]
    return [body, KeyNumber.made(N_("principal moments about O"), moments, unit="kg m²")]


def _significant(value: float, digits: int = 4) -> float:
    """`value` rounded to `digits` significant digits."""
    return float(f"{value:.{digits}g}")


def spin_text(body: str, moments: Sequence[float] | np.ndarray, k: float) -> str:
    """The Free body scene's note after "Spin it": which `body` was handed on and, if its
    principal moments [kg m²] were multiplied by k to fit the sliders, that and why it is the
    same motion."""
    text = f"Spun from the Inertia scene: {body}, about its middle axis y′."
    if k != 1.0:
        text += (f" Its moments ({', '.join(f'{m:.3g}' for m in moments)} kg m²) are shown ×{k:.3g} to fit the "
                 "sliders: the motion is the same (Euler's equations are homogeneous in I), T and L are ×k.")
    return text
