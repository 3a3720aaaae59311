"""What every scene's view shares: its place in a room, its messages, its presets, its removal.

`SceneView` is the base of a scene (see `app.kit` for the recipe).  A subclass sets the class
attributes `title`, `view` (its camera) and `preset_file`, builds its nodes under `root` and
its panel in `_build_scene` and `_build_gui` (keeping the top-level GUI handles in
`_gui_roots` and a `MessageLine` in `message`), implements `frame`, `refresh` and the
classmethods `simulation_from_preset` and `start_preset` (how a preset becomes a simulation,
and a new run of the room's one), and ends its `__init__` with `self.build()`.

Presets, once for every scene: `presets()` reads the scene's file once (`read_presets`, cached
per scene class), `new_simulation()` is `simulation_from_preset` of the first preset, and
`apply_preset(room, name)` follows one rule in every scene: **a preset starts paused at its
t = 0** (the room stops playing, the simulation starts the preset's run, every view redraws), so
that the lecturer can show the initial condition before pressing Play.

A scene whose room records its motion (`Room.history`: the simulation is replayable, see
`app.kit.core.history`) and that has a `transport` gets a `Timeline` (`app.kit.panel.timeline`) right
under it, built here; the room draws it after the view.

Its 3D labels are registered with `self.labels` (a `LabelLayer`: "this label, this priority"),
and its `frame` and `refresh` end by laying them out (`labels.update(dt)`, `labels.settle()`),
so that no two overlap on the screens that show them (the controlling browser's; a presenter's
and its followers' for a target with `screens`), nor cover the panel there.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from typing import Any, ClassVar
from weakref import WeakKeyDictionary

import viser

from app.i18n import N_, Said, for_gui
from app.kit.core.common import CameraView, SliderSpec, Wrap, apply_camera
from app.kit.core.key_number import KeyNumber
from app.kit.core.presets import PRESETS_DIR, Preset, load_presets
from app.kit.core.room import LIVE, Room
from app.kit.core.target import DrawTarget, as_target
from app.kit.draw.labels import LabelLayer
from app.kit.panel.binding import Binding, Clock, bind, install_typing_guard
from app.kit.panel.gui import MessageLine, Quiet, Tabs, Transport
from app.kit.panel.timeline import Timeline
from app.kit.run_words import RUN_MESSAGES
from app.viser_internals import panel_checkboxes, panel_inputs, remove_under

__all__ = ["PLOT_TABS", "SceneView", "nth"]

PLOT_TABS = ("Plots", "Energy", "Lagrange")
"""The panel tabs whose contents a presenter's followers see too, read only, while the presenter
has one open (`SceneView.room_plot`, `app.lecture.room_plot`)."""

_PRESETS: dict[type, tuple[Preset, ...]] = {}


def _held_checkboxes(view: SceneView) -> list[viser.GuiCheckboxHandle]:
    """The checkboxes held in the view's attributes, and in those of its parts (objects of the
    app, lists, dicts), two levels down; other views and rooms are not looked into."""
    found: dict[int, viser.GuiCheckboxHandle] = {}

    def visit(value: Any, depth: int) -> None:
        if isinstance(value, viser.GuiCheckboxHandle):
            found[id(value)] = value
            return
        if depth == 0 or isinstance(value, (SceneView, Room)):
            return
        if isinstance(value, dict):
            children: Any = value.values()
        elif isinstance(value, (list, tuple)):
            children = value
        elif type(value).__module__.startswith("app.") and hasattr(value, "__dict__"):
            children = vars(value).values()
        else:
            return
        for child in list(children):
            visit(child, depth - 1)

    for value in list(vars(view).values()):
        visit(value, 2)
    return list(found.values())


def nth(values: Callable[[], Sequence[Any]], index: int) -> Callable[[], Any]:
    """A getter of `values()[index]` (the value in force of one of a row of bound sliders)."""
    return lambda: values()[index]


class SceneView:
    """One browser's view of a room (the shared part of every scene)."""

    title: ClassVar[str] = ""
    root: str = "/scene"  # the scene node everything hangs under (prefixed for a broadcast view)
    view: ClassVar[CameraView] = CameraView((4.5, -3.6, 2.4), (0.0, 0.0, 0.0))
    preset_file: ClassVar[str] = ""  # under assets/presets/
    param_specs: ClassVar[tuple[SliderSpec, ...]] = ()
    rate_specs: ClassVar[tuple[SliderSpec, ...]] = ()
    simulation_parts: ClassVar[tuple[type | Callable[..., Any], ...]] = ()
    """What the scene's simulation holds from modules other than its own class's (a function a
    trace follows, a class of another module): the room codec decodes nothing else
    (`app.scenes.simulation_parts`; an encoding error names what is missing)."""
    tabs: Tabs | None = None
    """The panel's tabs (Setup / Readout / ...), if the scene has them."""
    open_scene: Callable[[str, Callable[[Room], None]], Room] | None = None
    """Set by the session: open the scene `title` in this browser with a new room, after
    `prepare(room)` has set its simulation up; returns that room.  A scene hands a body to
    another by title, never by importing it ("Spin it": `self.open_scene("Free body", prepare)`)."""
    start_own_preset: Callable[[str], None] | None = None
    """Set by the session: start the lecturer's own preset `name` (`app.own`) in this view's room."""
    clock: Clock | None = None  # the bindings' time (None: time.monotonic); tests set a ManualClock
    timeline: Timeline | None = None
    transport: Transport | None = None
    """The transport (`build_head`), if the scene has motion."""
    """The replay's slider and buttons under the transport, if the room records its motion."""

    def __init__(self, client: viser.ClientHandle | DrawTarget, room: Room, wrap: Wrap,
                 report_error: Callable[[str, BaseException], None] | None = None) -> None:
        target = as_target(client)
        self.client = target
        # Interactive handles (gizmos, click handlers) go here and nowhere else: the scene of
        # the one browser that controls the room, or None (app.kit.core.target).
        self.controls = target.controls
        # A presenter's view draws into the shared scene under a prefix (app.lecture.lectern.Broadcast).
        self.root = target.root_prefix + type(self).root
        self.room = room
        self.sim: Any = room.sim
        self.tr = for_gui(target.gui)
        """The browser's words and numbers (`app.i18n.Translator`), chosen per browser by its session."""
        self._wrap = wrap
        self._report_error = report_error
        self.quiet = Quiet()  # the server writing sliders: their callbacks do nothing
        self.message: MessageLine
        self._gui_roots: list[Any] = []
        self._bindings: list[Binding] = []
        self._in_force: WeakKeyDictionary[Binding, tuple[Callable[[], Any], SliderSpec | None]] = \
            WeakKeyDictionary()
        """binding -> (the value in force, read from the simulation; the slider's spec): what
        the followers read (`in_force`), never the widget, which may be stale."""
        self._root_node = target.scene.add_frame(self.root, show_axes=False)
        # Every 3D label of the view is registered here with a priority; `frame` ends with
        # `self.labels.update(dt)` and `refresh` with `self.labels.settle()` (app.kit.draw.labels).
        # A target drawn for many screens (a presenter's shared scene) names them (`screens`).
        self.labels = LabelLayer(target.camera, type(self).view, getattr(target, "screens", None))

    def build(self) -> None:
        """Build the nodes and the panel (`_build_scene`, `_build_gui`), join the room, draw."""
        with self.client.atomic():
            self._build_scene()
            self._build_gui()
            self._build_timeline()
            self._gui_roots.append(install_typing_guard(self.client.gui))  # typed numbers arrive as typed
        self.room.add_view(self)
        self.refresh()
        if self.timeline is not None:
            self.timeline.refresh()

    def _build_timeline(self) -> None:
        """The replay's `Timeline` right under the transport's status line, if the room records."""
        transport = self.transport
        if self.room.history is None or transport is None:
            return
        order = transport.gui_status.order
        self.timeline = Timeline(self.client.gui, self._wrap, self.message, self.room,
                                 order=float(order) if isinstance(order, int | float) else None, clock=self.clock,
                                 tr=self.tr)
        room = self.room
        transport.looking_back = lambda: room.mode != LIVE  # the Timeline's status says the time then
        self._bindings.append(self.timeline.binding)
        self._gui_roots.extend(self.timeline.handles)

    def build_head(self, intro: str, **transport_options: Any) -> None:
        """The top of a scene's panel: its intro (Markdown), the message line and the transport
        (Play / Pause, Step · Reset, time scale: `app.kit.panel.gui.Transport`, calling the room;
        `transport_options` such as `integrators=`, `on_integrator=`)."""
        gui, room = self.client.gui, self.room
        self.gui_intro = gui.add_markdown(intro)
        self.message = MessageLine(gui)
        self.transport = Transport(gui, self._wrap, self.message, on_toggle=room.toggle, on_step=room.step,
                                   on_reset=room.reset, on_time_scale=room.set_time_scale, clock=self.clock,
                                   tr=self.tr, **transport_options)

    def _build_scene(self) -> None:
        """Add the scene's nodes under `root`."""

    def _build_gui(self) -> None:
        """Add the panel; keep its top-level handles in `_gui_roots`."""

    # ------------------------------------------------------------------ presets
    @classmethod
    def check_preset(cls, preset: Preset) -> None:
        """A scene's own test of a preset (ValueError with a message); none by default."""

    @classmethod
    def read_presets(cls) -> tuple[Preset, ...]:
        """Read the scene's preset file now (PresetError naming the file and the field):
        assets/presets/<preset_file> against `param_specs`, `rate_specs` and `check_preset`.  A
        scene whose file has fields of its own overrides this (and only this: `presets` caches)."""
        return load_presets(PRESETS_DIR / cls.preset_file, cls.param_specs, cls.rate_specs, check=cls.check_preset)

    @classmethod
    def presets(cls) -> tuple[Preset, ...]:
        """The scene's presets, read once per scene class (`read_presets`; PresetError if broken)."""
        if cls not in _PRESETS:
            _PRESETS[cls] = cls.read_presets()
        return _PRESETS[cls]

    @classmethod
    def preset(cls, name: str) -> Preset:
        """The preset `name`; ValueError naming the valid ones."""
        for preset in cls.presets():
            if preset.name == name:
                return preset
        raise ValueError(f"{cls.title} has no preset {name!r}; "
                         f"the presets are {', '.join(p.name for p in cls.presets())}")

    @classmethod
    def simulation_from_preset(cls, preset: Preset) -> Any:
        """A new simulation at the preset's t = 0 (the scene's part of `new_simulation`)."""
        raise NotImplementedError

    @classmethod
    def start_preset(cls, sim: Any, preset: Preset) -> None:
        """Start the preset's run in the room's simulation `sim`, at its t = 0 (the scene's part
        of `apply_preset`): the same object, since the views draw it and hold its traces."""
        raise NotImplementedError

    @classmethod
    def new_simulation(cls) -> Any:
        """A simulation at the scene's first preset (its `preset` names it)."""
        first = cls.presets()[0]
        sim = cls.simulation_from_preset(first)
        sim.preset = first.name
        return sim

    @classmethod
    def apply_preset(cls, room: Room, name: str) -> None:
        """Load the preset `name` into the room (ValueError naming the valid ones): the rule of
        every scene, a preset starts **paused at its t = 0**; every view of the room redraws."""
        preset = cls.preset(name)
        cls.start_preset(room.sim, preset)
        room.sim.preset = name
        room.pause()  # every view redraws

    @classmethod
    def moment_preset(cls, room: Room, name: str) -> Preset:
        """The moment `room` shows as a preset named `name` (its parameters, attitude and rates now,
        to start at t = 0): what `Save as preset` keeps (`app.own`).  ValueError where the scene
        cannot say its moment in its preset's terms (by default: every scene that does not say how)."""
        raise ValueError(f"{cls.title} cannot keep what it shows as a preset yet")

    def show_own_presets(self, names: Sequence[str]) -> None:
        """List the lecturer's own presets of the scene beside its own (the presets row's ★ Mine row)."""
        row = getattr(self, "presets_row", None)
        if row is not None:
            row.show_own(names)

    def choose_own_preset(self, name: str) -> None:
        """A button of the ★ Mine row."""
        if self.start_own_preset is None:
            self.message.show(Said(N_("No preset named {name}."), name=repr(name)))
            return
        try:
            self.start_own_preset(name)
        except ValueError:  # a name a client made up, or one deleted meanwhile
            self.message.show(Said(N_("No preset named {name}."), name=repr(name)))

    def choose_preset(self, name: str) -> None:
        """A preset button: a name the scene does not have (a client can send any) is refused."""
        if name not in {p.name for p in self.presets()}:
            self.message.show(Said(N_("No preset named {name}."), name=repr(name)))
            return
        self.message.clear()
        self.apply_preset(self.room, name)

    def preset_shown(self) -> Preset | None:
        """The preset the room's run started from, if it did."""
        name = getattr(self.sim, "preset", None)
        return next((p for p in self.presets() if p.name == name), None)

    # ------------------------------------------------------------------ the view protocol
    def frame(self, dt: float) -> None:
        raise NotImplementedError

    def refresh(self) -> None:
        raise NotImplementedError

    def show_message(self, text: str, stale: Callable[[], bool] | None = None) -> None:
        """Say `text` in the message line, until `stale()` says it no longer holds; a run's stop
        the room says in English (`app.kit.run_words.RUN_MESSAGES`) in this view's language."""
        self.message.show(functools.partial(RUN_MESSAGES.in_language, text), stale)

    gizmos_hidden = False
    """True while the browser renders a screenshot: the drag gizmos stay hidden (`hide_gizmos`)."""

    def gizmo_handles(self) -> list[Any]:
        """The view's drag gizmos (transform controls in `self.controls`); none by default."""
        return []

    def hide_gizmos(self, hidden: bool) -> None:
        """Hide the drag gizmos (a screenshot is taken), or show them again as the view's state
        says (`refresh`)."""
        self.gizmos_hidden = bool(hidden)
        if hidden:
            for gizmo in self.gizmo_handles():
                gizmo.visible = False
        else:
            self.refresh()

    def report_error(self, where: str, error: BaseException) -> None:
        if self._report_error is None:
            raise error
        self._report_error(where, error)

    def reset_view(self) -> None:
        """Put this client's camera back to the scene's view."""
        if self.client.camera is not None:
            apply_camera(self.client, self.view)

    @property
    def gui_roots(self) -> tuple[Any, ...]:
        """The top-level handles of the view's panel (what a narrow explorer's panel folds), with
        the refusal notes under its bound controls (a control at the panel's root has its note
        there too)."""
        return (*self._gui_roots, *(binding.note.handle for binding in self._all_bindings()
                                    if binding.note is not None and binding.active))

    def _all_bindings(self) -> list[Binding]:
        """The view's bindings: its own (`bind`, the Timeline's) and the transport's time scale."""
        transport = self.transport
        return [*self._bindings, *([transport.time_scale_binding] if transport is not None else [])]

    def remove(self) -> None:
        """Leave the room and remove this view's panel and nodes from its client."""
        self.remove_panel()
        self._root_node.remove()  # and every node below it

    def remove_panel(self) -> None:
        """Leave the room and remove the panel; the nodes stay as last drawn (a presenter who
        stops leaves the last state on the followers' screens)."""
        self.room.remove_view(self)
        for binding in self._all_bindings():
            binding.close()  # (its note goes before the folders it is in)
        self._bindings = []
        for handle in self._gui_roots:
            handle.remove()
        self._gui_roots = []
        self._remove_controls()

    def _remove_controls(self) -> None:
        """Remove what the view added to a controlling browser's own scene (a presenter's
        gizmos and clickable copies, named under `root`); in a browser's own room they went
        with the root node."""
        controls = self.controls
        if controls is None or controls is self.client.scene:
            return
        remove_under(controls, self.root)

    def checkboxes(self) -> dict[str, viser.GuiCheckboxHandle]:
        """The view's checkboxes by English label (what a lesson step may switch, whatever the
        browser's language): every checkbox of its
        panel, found in the panel's tree below the view's top-level handles (`_gui_roots`), or,
        without viser's panel registry (`app.viser_internals.PANEL_INPUTS`), every checkbox the
        view or its parts hold."""
        found = panel_checkboxes(self.client.gui, self._gui_roots)
        if found is None:
            found = _held_checkboxes(self)
        by_english = {}  # by every English label the handle's shows (two msgids may share a translation)
        for handle in found:
            for english in self.tr.englishes(str(handle.label)) or (str(handle.label),):
                by_english[english] = handle
        return by_english

    def panel_controls(self) -> list[Any]:
        """The inputs of the view's panel (buttons, rows of buttons, sliders, checkboxes, menus):
        what only the browser controlling the room has, so a lesson's words must not ask a
        follower for them (tests/test_lesson_words.py); [] without viser's panel registry."""
        return panel_inputs(self.client.gui, self._gui_roots) or []

    def show_tab(self, name: str) -> None:
        """Open the panel tab `name` (a lesson step); ValueError if the scene has no such tab."""
        if self.tabs is None or name not in self.tabs.names:
            raise ValueError(f"{self.title} has no panel tab {name!r}")
        self.tabs.show(name)

    def room_plot(self) -> tuple[str, list[Any]]:
        """(tab, elements): the plot tab this view's browser has open (one of PLOT_TABS) and the
        panel elements it shows (uPlot charts and Markdown, in order), which a presenter's
        followers see copied (`app.lecture.room_plot.PlotMirror`); ("", []) when no plot tab is open."""
        tabs = self.tabs
        if tabs is None or tabs.shown not in PLOT_TABS:
            return "", []
        elements = self.plot_elements(tabs.shown)
        return (tabs.shown, elements) if elements else ("", [])

    def plot_elements(self, tab: str) -> list[Any]:
        """The panel elements of the plot tab `tab` (one of PLOT_TABS) that followers see copied;
        scenes with plot tabs override it (none by default)."""
        return []

    def set_integrator(self, name: str) -> None:
        """Choose the integrator `name` (a lesson step); scenes with an integrator menu override it."""
        raise ValueError(f"{self.title} has no integrator menu (asked for {name!r})")

    def key_numbers(self) -> list[KeyNumber]:
        """The scene's key numbers, for the followers' read-only panel: by default each bound
        slider's English label and its value in force, read from the room's simulation now
        (`in_force`) whatever tab the browser shows, rounded to the slider's step."""
        timeline = self.timeline.binding if self.timeline is not None else None
        return [KeyNumber.made(self.tr.english(str(b.handle.label)), (self.in_force(b),)) for b in self._bindings
                if isinstance(b.handle, viser.GuiSliderHandle) and b is not timeline]

    def in_force(self, binding: Binding) -> float:
        """The value in force of a bound control, from the simulation (`bind`'s `current`),
        rounded to its slider's step, not the slider's widget (a view does not keep its sliders
        current while another tab shows); the widget's value for a control not bound through `bind`."""
        source = self._in_force.get(binding)
        if source is None:
            return float(binding.handle.value)
        current, spec = source
        value = float(current())
        return spec.rounded(value) if spec is not None else value

    # ------------------------------------------------------------------ bound controls
    def bind(self, handle: Any, where: str, apply: Callable[[Any], str | None], current: Callable[[], Any],
             spec: SliderSpec | None = None, check: Callable[[Any], Any] | None = None) -> Binding:
        """Bind a control of this view to a simulation value (`app.kit.panel.binding.bind`): each value
        the browser sends is checked by `spec` or `check` and `apply`'d when it arrives, or refused
        right under the control (and in the message line) with the field back at `current()`."""
        binding = bind(handle, where=where, wrap=self._wrap, message=self.message, quiet=self.quiet, apply=apply,
                       current=current, spec=spec, check=check, clock=self.clock, gui=self.client.gui)
        self._bindings.append(binding)
        self._in_force[binding] = (current, spec)
        return binding

    def show_values(self, handles: Sequence[Any], specs: Sequence[SliderSpec], values: Sequence[float],
                    skip: Any = None) -> None:
        """Show `values` on sliders (rounded to their steps), their callbacks silenced.  A slider
        that already shows a value rounding to the same is left alone (a typed -0.8 stays -0.8
        on a slider of step 1), and so is one its user is editing."""
        for handle, spec, value in zip(handles, specs, values):
            if handle is skip:
                continue
            shown = spec.rounded(value)
            try:
                same = spec.rounded(float(handle.value)) == shown
            except (TypeError, ValueError):
                same = False
            if not same:
                self.quiet.write(handle, shown)
