"""The Build tab: a DH table edited in the browser, drawn live, downloaded; a URDF uploaded.

The lower panel is ~400 × 280 px, so the table is not a grid of inputs: a compact read-only
table shows every row (the selected one highlighted) with the message line under it, and one
set of inputs under it edits the selected row (joint type, a, α, d, θ offset, limits; a bad
value's message is repeated under them). Buttons add a row after the selected one, remove it or
move it up or down. Every change builds the robot with
:func:`app.core.build_table.build` and dispatches :class:`~app.core.actions.EditRobot`; a bad value is named
under the table (row and field) and nothing is dispatched, so the last good robot stays drawn.
Widgets are made once: a change of the table only updates values and the row list.

The editor holds its table as form state (what is typed, like any input's value); the robot, q
and everything drawn live in the tab's state.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import threading
from collections.abc import Callable, Sequence
from typing import Any, cast

import viser

import robots
from kinematics import Robot
from kinematics.errors import JacobianLabError

from ...core import build_table as dt
from ...core.actions import EditRobot
from ...core.commands import RequestDownload, UploadRobot
from ...core.downloads import EXPORT_FORMATS
from ...core.i18n import N_, Translator, translations
from ...core.numbers import NumberError, parse_number
from ...viser_adapter import MAX_UPLOAD_BYTES, is_removed, upload_too_large
from .. import fmt
from .common import Dispatch

__all__ = ["EditorPanel", "EMPTY", "DOWNLOADS"]

EMPTY = N_("empty table (one joint)")
"""The "Start from" entry of a fresh one-row table (English; shown in the tab's language)."""
ROW_BUTTONS = (N_("+ Add"), N_("− Remove"), N_("↑ Up"), N_("↓ Down"))
DOWNLOADS = {"TOML": "Robot file (TOML)", "URDF": "URDF", **{f"J {k}": k for k in EXPORT_FORMATS}}
_KINDS = (N_("revolute"), N_("prismatic"))
_CONVENTIONS = (N_("standard"), N_("modified"))
"""Download button → :class:`~app.core.actions.RequestDownload` label."""

_CSS = """<style>
.jl-dh{width:calc(100% - 12px);margin:0 6px;border-collapse:collapse;
  font:12px/1.35 ui-monospace,Menlo,Consolas,monospace;font-variant-numeric:tabular-nums}
.jl-dh th{font-weight:600;color:#495057;text-align:right;padding:0 4px;border-bottom:1px solid #ced4da}
.jl-dh td{text-align:right;padding:0 4px;white-space:nowrap}
.jl-dh tr.sel td{background:#e7ecfb;font-weight:600}
.jl-dh td.bad{color:#96001a;background:#fff4f4;font-weight:700}
.jl-dh-msg{font:12px/1.35 system-ui,sans-serif;margin:3px 8px 0 8px}
.jl-dh-msg.bad{color:#b3261e}.jl-dh-msg.ok{color:#495057}
</style>"""


def library_dh_robots() -> list[str]:
    """Library robots that have a DH table (every robot file of ``robots/data``)."""
    return [n for n in robots.names() if robots.load(n).dh is not None]


class EditorPanel:
    """The Build tab's handles and the table being edited.

    Attributes:
        table: The table as typed (degrees on screen).
        selected: Index of the row the inputs edit.
        error: The message shown for a bad value ("" when the table builds).
        built: The last robot built from the table (``None`` before the first edit).
    """

    def __init__(
        self,
        gui: viser.GuiApi,
        dispatch: Dispatch,
        library: Sequence[str],
        order: float,
        tr: Translator | None = None,
    ) -> None:
        self.tr = tr = tr or translations()
        _ = tr.gettext
        # What the dropdowns and buttons show ↔ the values they stand for (English: the same).
        self._shown = {k: _(k) for k in (EMPTY, *ROW_BUTTONS, *_KINDS, *_CONVENTIONS)}
        self._value = {v: k for k, v in self._shown.items()}
        self.gui, self.dispatch = gui, dispatch
        self.table = dt.empty()
        self.selected = 0
        self.error = ""
        self._bad: tuple[int, str] = (0, "")  # (row from 1, field) of the value the error names
        self.built: Robot | None = None
        self._pending: tuple[int | None, ...] = (None,)  # table row → joint of the robot last dispatched
        self._lock = threading.RLock()
        self._quiet = False
        self.root = gui.add_folder(None, order=order)
        with self.root:
            self.start = gui.add_dropdown(
                _("Start from"),
                (self._shown[EMPTY], *library),
                initial_value=self._shown[EMPTY],
                hint=_("Copy a library robot's DH table (its base and tool transforms kept), or one joint."),
            )
            self.convention = gui.add_dropdown(
                _("Convention"),
                tuple(self._shown[c] for c in _CONVENTIONS),
                hint=_(
                    "standard: A = Rz(θ) Tz(d) Tx(a) Rx(α); modified (Craig): A = Rx(α) Tx(a) Rz(θ) Tz(d)"
                ),
            )
            self.summary = gui.add_html("")
            self.row = gui.add_dropdown(_("Edit row"), ("1",), hint=_("The row the inputs below edit."))
            self.kind = gui.add_dropdown(_("Joint"), tuple(self._shown[k] for k in _KINDS))
            # Text boxes, read by app.core.numbers: what is typed is kept ("1e-3", "0.15005"), and
            # what is not a number is refused in words (a number box would mangle it silently).
            self.a = gui.add_text("a [m]", "0", hint=_("Link length: along x(i)"))
            self.alpha = gui.add_text("α [°]", "0", hint=_("Link twist: about x(i)"))
            self.d = gui.add_text("d [m]", "0", hint=_("Link offset: along z(i-1)"))
            self.theta = gui.add_text(_("θ offset [°]"), "0", hint=_("Added to q (revolute)"))
            self.lower = gui.add_text(_("Lower limit [°]"), "-180", hint=_("The joint's lower limit"))
            self.upper = gui.add_text(_("Upper limit [°]"), "180", hint=_("The joint's upper limit"))
            self.problem = gui.add_html("")  # the message again, in sight of the inputs
            self.rows = gui.add_button_group(_("Rows"), tuple(self._shown[b] for b in ROW_BUTTONS))
            self.download = gui.add_button_group(_("Download"), tuple(DOWNLOADS))
            self.upload = gui.add_upload_button(
                _("Upload a URDF (at most {size} MB)").format(size=MAX_UPLOAD_BYTES // (1024 * 1024)),
                icon=viser.Icon.UPLOAD,
                mime_type=".urdf,.xml,application/xml,text/xml",
                hint=_("Only this tab sees it; its meshes are not loaded (generated geometry is drawn)."),
            )
        value = lambda v: self._value.get(str(v), str(v))  # noqa: E731  (a shown label → its value)
        self._on(self.start, lambda v: self.start_from(value(v)))
        self._on(self.convention, lambda v: self._edit(convention=value(v)))
        self._on(self.row, lambda v: self.select(int(str(v)) - 1) if str(v).isdigit() else None)
        self._on(self.kind, lambda v: self.set_field("joint", value(v)))
        for field, handle in self._fields():
            self._on(handle, functools.partial(self.set_field, field))
        self.rows.on_click(lambda event: self._guarded(self.row_operation, value(event.target.value)))
        self.download.on_click(lambda event: dispatch(RequestDownload(DOWNLOADS[str(event.target.value)])))
        self.upload.on_upload(lambda event: self._uploaded(event.target.value))
        with self._lock:
            self._show_inputs()
            self._show_summary()

    # ------------------------------------------------------------------ user input
    def _on(self, handle: viser.GuiInputHandle, fn: Callable[[object], object]) -> None:
        def callback(event: viser.GuiEvent) -> None:
            if not is_removed(event.target):
                self._guarded(fn, event.target.value)

        handle.on_update(callback)

    def _guarded(self, fn: Callable[[object], object], value: object) -> None:
        with self._lock:
            if not self._quiet:
                fn(value)

    def _uploaded(self, file: object) -> None:
        refused = upload_too_large(file)
        if refused is not None:
            self.dispatch(UploadRobot(refused[0], b"", refused[1]))
            return
        name, content = getattr(file, "name", ""), getattr(file, "content", b"")
        data = bytes(content) if isinstance(content, (bytes, bytearray)) else b""
        self.dispatch(UploadRobot(str(name), data))

    def start_from(self, name: str) -> None:
        """Replace the table by ``name``'s DH table (a library robot) or by :data:`EMPTY`'s one row."""
        if self._shown.get(name, name) not in self.start.options:  # a library robot's name, never a path
            self.error = self.tr.gettext(
                "“Start from” takes one of its options: {name} is not one of them."
            ).format(name=repr(name[:60]))
            self._show_summary()
            return
        try:
            table = dt.empty() if name == EMPTY else dt.from_robot(robots.load(name))
        except JacobianLabError as exc:
            self.error = str(exc)
            self._show_summary()
            return
        self.table, self.selected = table, 0
        self._changed(tuple(None for _ in table.rows), inputs=True)

    def select(self, index: int) -> None:
        """Edit row ``index`` (0-based)."""
        if 0 <= index < len(self.table.rows):
            self.selected = index
            self._show_inputs()
            self._show_summary()

    def _fields(self) -> tuple[tuple[str, viser.GuiTextHandle], ...]:
        return (
            ("a", self.a),
            ("alpha", self.alpha),
            ("d", self.d),
            ("theta", self.theta),
            ("lo", self.lower),
            ("hi", self.upper),
        )

    def set_field(self, field: str, value: object) -> None:
        """Set ``field`` ("joint", "a", "alpha", "d", "theta", "lo", "hi") of the selected row to
        ``value`` as typed (degrees; checked when the table is built)."""
        row = self.table.rows[self.selected]
        changes: dict[str, Any] = {field: value}
        row = row.with_kind(str(value)) if field == "joint" else dataclasses.replace(row, **changes)
        self._replace_row(row, inputs=field == "joint")

    def set_limits(self, value: object) -> None:
        """Set the selected row's limits to ``value`` = (lower, upper) [° | m]."""
        lo, hi = tuple(cast(Sequence[object], value))
        self._replace_row(dataclasses.replace(self.table.rows[self.selected], lo=lo, hi=hi))

    def row_operation(self, label: object) -> None:
        """One of :data:`ROW_BUTTONS`: add a row after the selected one, remove it, move it up or down."""
        rows, i, n = list(self.table.rows), self.selected, len(self.table.rows)
        order: list[int | None] = list(range(n))
        if label == ROW_BUTTONS[0]:
            if n >= dt.MAX_ROWS:
                self.error = self.tr.gettext(
                    "A table has at most {most} rows: remove one before adding another."
                ).format(most=dt.MAX_ROWS)
                self._show_summary()
                return
            rows.insert(i + 1, dt.Row(a=0.3))
            order.insert(i + 1, None)
            i += 1
        elif label == ROW_BUTTONS[1]:
            if n == 1:
                self.error = self.tr.gettext("A robot needs at least one joint: row 1 cannot be removed.")
                self._show_summary()
                return
            del rows[i], order[i]
            i = min(i, n - 2)
        elif label in ROW_BUTTONS[2:]:
            j = i - 1 if label == ROW_BUTTONS[2] else i + 1
            if not 0 <= j < n:
                return
            rows[i], rows[j] = rows[j], rows[i]
            order[i], order[j] = order[j], order[i]
            i = j
        else:
            return
        self.table = dataclasses.replace(self.table, rows=tuple(rows), configurations=())
        self.selected = i
        self._changed(tuple(order), inputs=True)

    # ------------------------------------------------------------------ table → robot
    def _replace_row(self, row: dt.Row, inputs: bool = False) -> None:
        rows = list(self.table.rows)
        rows[self.selected] = row
        self._edit(rows=tuple(rows), inputs=inputs)

    def _edit(self, inputs: bool = False, **changes: object) -> None:
        self.table = dataclasses.replace(self.table, **changes)  # type: ignore[arg-type]
        self._changed(tuple(range(len(self.table.rows))), inputs)

    def _changed(self, order: tuple[int | None, ...], inputs: bool) -> None:
        """The table changed (``order[i]``: the previous row that row ``i`` was, ``None`` if new)."""
        self._pending = tuple(None if k is None else self._pending[k] for k in order)
        if inputs:
            self._show_inputs()
        try:
            robot = dt.build(self.table, self.tr)
        except dt.TableError as exc:
            self.error, self._bad = str(exc), (exc.row, exc.field)
        else:
            self.error, self.built, self._bad = "", robot, (0, "")
            self.dispatch(EditRobot(dt.BUILT_NAME, robot, self._pending))
            self._pending = tuple(range(len(self.table.rows)))
        self._show_summary()

    # ------------------------------------------------------------------ drawing
    def _show_inputs(self) -> None:
        """Put the selected row on the inputs (their callbacks ignored meanwhile) and list the rows."""
        row = self.table.rows[self.selected]
        self._quiet = True
        try:
            options = tuple(str(i + 1) for i in range(len(self.table.rows)))
            if self.row.options != options:
                self.row.options = options
            _set(self.row, str(self.selected + 1))
            _set(self.convention, self._shown.get(self.table.convention, self.table.convention))
            _set(self.kind, self._shown.get(row.joint, row.joint))
            for field, handle in self._fields():
                _set(handle, _typed(getattr(row, field), self.tr))
            revolute = row.joint == "revolute"
            _ = self.tr.gettext
            self.lower.label = _("Lower limit [°]") if revolute else _("Lower limit [m]")
            self.upper.label = _("Upper limit [°]") if revolute else _("Upper limit [m]")
            self.theta.label = _("θ offset [°]") if revolute else "θ [°]"
            self.d.label = "d [m]" if revolute else _("d offset [m]")
        finally:
            self._quiet = False

    def _show_summary(self) -> None:
        tr = self.tr
        _ = tr.gettext
        limits = fmt.escape(_("limits"))
        head = f"<tr><th>#</th><th></th><th>a</th><th>α°</th><th>d</th><th>θ°</th><th>{limits}</th></tr>"
        body = []
        for i, r in enumerate(self.table.rows):
            unit = "°" if r.joint == "revolute" else " m"
            cells = [str(i + 1), "R" if r.joint == "revolute" else "P"]
            cells += [_cell(r.a, tr), _cell(r.alpha, tr), _cell(r.d, tr), _cell(r.theta, tr)]
            cells.append(f"{_cell(r.lo, tr)}…{_cell(r.hi, tr)}{unit}")
            # The value the error names is shown as typed, marked (the arm keeps its last good table).
            bad = {"a": 2, "alpha": 3, "d": 4, "theta": 5, "lo": 6, "hi": 6}.get(self._bad[1], -1)
            bad = bad if self.error and self._bad[0] == i + 1 else -1
            cls = ' class="sel"' if i == self.selected else ""
            body.append(
                f"<tr{cls}>"
                + "".join(
                    f'<td class="bad" title="{fmt.escape(self.error)}">{fmt.escape(c)} ⚠</td>'
                    if k == bad
                    else f"<td>{fmt.escape(c)}</td>"
                    for k, c in enumerate(cells)
                )
                + "</tr>"
            )
        if self.error:
            msg = f'<div class="jl-dh-msg bad" role="alert">⚠ {fmt.escape(self.error)}</div>'
        else:
            n = len(self.table.rows)
            convention = self._shown.get(self.table.convention, self.table.convention)
            what = tr.ngettext("{n} joint, {convention} DH", "{n} joints, {convention} DH", n).format(
                n=n, convention=convention
            )
            if self.table.source:
                what += _(", from {robot} (its base and tool transforms kept)").format(
                    robot=self.table.source
                )
            state = _("drawn live") if self.built is not None else _("edit a value to draw it")
            msg = f'<div class="jl-dh-msg ok">{fmt.escape(what)}: {fmt.escape(state)}.</div>'
        self.summary.content = f'{_CSS}<table class="jl-dh">{head}{"".join(body)}</table>{msg}'
        self.problem.content = msg if self.error else ""

    def remove(self) -> None:
        self.root.remove()


def _set(handle: Any, value: object) -> None:
    handle.value = value


def _typed(value: object, tr: Translator) -> str:
    """What an input shows: the text as typed, or a number in its shortest exact form (0.15005; 0,15005
    in a language with a decimal comma)."""
    if isinstance(value, str):
        return value
    try:
        return tr.decimal(format(float(value), ".12g"))  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        return str(value)


def _cell(value: object, tr: Translator) -> str:
    """A table cell: a number in 4 significant figures, anything else (1e400, NaN, 0,3) as typed."""
    typed = value
    if isinstance(typed, str):
        try:
            value = parse_number(typed, tr=tr)  # "0,3" typed in Portuguese is 0.3
        except NumberError:
            return typed.strip()[:8]
    try:
        x = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        return str(value).strip()[:8]
    return tr.decimal(f"{x:.4g}") if math.isfinite(x) else str(value).strip()[:8]
