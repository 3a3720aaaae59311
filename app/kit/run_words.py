"""A run's stop and an integrator's refusal as a person reads them: in their browser's language.

The simulation and the room write these in English (the logs, `python -m physics`): the room's
"The simulation stopped: ..." (`app.kit.core.room.Room._advance`, said in every view), a rigid
body's "euler_lagrange stopped: ... Press Play to go on with splitting4."
(`app.kit.rigid.simulation.RigidBodySimulation`, where the Euler-angle Lagrangian reaches gimbal
lock) and "euler_lagrange cannot go on from here: ... Staying with splitting4." (its
`set_integrator`, the Integrator dropdown at a state the method cannot start from).
The room's "Replay reached the live moment, t = ... s." too, and the note on a copy of a lecture's
room that is not exact (`app.lecture.bus.rooms.RemoteRooms._orphan_copy`: "The presenter's worker ...").
`RUN_MESSAGES.in_language` writes them in a view's language; the methods' names (as the dropdown
shows them) stay, the numbers take the language's decimal sign.

    RUN_MESSAGES.in_language("The simulation stopped: non-finite state", translator("de"))
    # "Die Simulation wurde angehalten: non-finite state" (physics' own words where no entry knows them)
"""

from __future__ import annotations

from app.i18n import N_, Phrases

__all__ = ["METHOD_REFUSALS", "RUN_MESSAGES", "SINGULARITIES"]

_NUMBER = r"-?[0-9.]+(?:e[-+]?[0-9]+)?|-?inf|nan"  # a number as Python's :g (or .3g, .9g) writes it
_METHOD = r"[\w-]+"  # a method's name in `physics.methods`

_SINGULAR = (r"the Euler-angle Lagrangian is singular at θ = (?P<theta>{n}) rad \(sin θ in a denominator, "
             r"sin θ = (?P<sin_theta>{n})\) reached at t = (?P<t>{n}) s{detail}; use another method "
             r"\(e\.g\. 'adaptive' or 'splitting4', which have no singularity\)")

SINGULARITIES = Phrases(
    (_SINGULAR.format(n=_NUMBER, detail=r" \(the starting state\)"),
     N_("the Euler-angle Lagrangian is singular at θ = {theta} rad (sin θ in a denominator, sin θ = {sin_theta}) "
        "reached at t = {t} s (the starting state); use another method (e.g. 'adaptive' or 'splitting4', which "
        "have no singularity)")),
    (_SINGULAR.format(n=_NUMBER, detail=rf" \(sin θ fell to (?P<stop>{_NUMBER})\)"),
     N_("the Euler-angle Lagrangian is singular at θ = {theta} rad (sin θ in a denominator, sin θ = {sin_theta}) "
        "reached at t = {t} s (sin θ fell to {stop}); use another method (e.g. 'adaptive' or 'splitting4', which "
        "have no singularity)")),
    (_SINGULAR.format(n=_NUMBER, detail=r" \(trial stage of a step\)"),
     N_("the Euler-angle Lagrangian is singular at θ = {theta} rad (sin θ in a denominator, sin θ = {sin_theta}) "
        "reached at t = {t} s (trial stage of a step); use another method (e.g. 'adaptive' or 'splitting4', which "
        "have no singularity)")),
    numbers=("theta", "sin_theta", "t", "stop"),
)
"""`physics.lagrange.EulerLagrangeSingularityError`'s words (where the method's coordinates fail)."""

METHOD_REFUSALS = Phrases(
    (rf"(?P<name>{_METHOD}) cannot go on from here: (?P<reason>.+)\. Staying with (?P<kept>{_METHOD})\.",
     N_("{name} cannot go on from here: {reason}. Staying with {kept}.")),
    (rf"(?P<stopped>{_METHOD}) stopped: (?P<reason>.+)\. Press Play to go on with (?P<going_on>{_METHOD})\.",
     N_("{stopped} stopped: {reason}. Press Play to go on with {going_on}.")),
    nested={"reason": SINGULARITIES},
)
"""A rigid body's integrator refused or stopped (`RigidBodySimulation.set_integrator`, `advance`)."""

RUN_MESSAGES = Phrases(
    (r"The simulation stopped: (?P<error>.+)", N_("The simulation stopped: {error}")),
    (rf"(?P<error>{_METHOD} (?:cannot go on from here|stopped): .+)", "{error}"),
    (rf"\*\*Replay reached the live moment, t = (?P<t>{_NUMBER}) s\.\*\*",
     N_("**Replay reached the live moment, t = {t} s.**")),
    (rf"The presenter's worker is gone: this is the last state of its room that this server saw "
     rf"\(t = (?P<t>{_NUMBER}) s\), paused\.",
     N_("The presenter's worker is gone: this is the last state of its room that this server saw "
        "(t = {t} s), paused.")),
    (rf"The presenter's worker does not answer: this is the last state of its room that this server saw "
     rf"\(t = (?P<t>{_NUMBER}) s\), paused\.",
     N_("The presenter's worker does not answer: this is the last state of its room that this server saw "
        "(t = {t} s), paused.")),
    (r"The presenter's worker is gone and none of its room reached this server: only the scene "
     r"\((?P<title>.+)\) could be kept, in a fresh room\.",
     N_("The presenter's worker is gone and none of its room reached this server: only the scene "
        "({title}) could be kept, in a fresh room.")),
    (r"The presenter's worker does not answer and none of its room reached this server: only the scene "
     r"\((?P<title>.+)\) could be kept, in a fresh room\.",
     N_("The presenter's worker does not answer and none of its room reached this server: only the scene "
        "({title}) could be kept, in a fresh room.")),
    nested={"error": METHOD_REFUSALS}, numbers=("t",),
)
"""What a view's message line says about its run, matched in English (`SceneView.show_message`)."""
