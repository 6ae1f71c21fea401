"""The panel's layout on a projector: a panel that scales with the screen, the split between the joints
and the views of J set by what they hold, a scroll cue wherever something is cut, legible colours.

viser docks our two panels (the main one: robot, status, joints; under it the views of J) in one right
column of fixed width whose split it sets once. On a 1280×720 projector that left the views 206 px
while the joints' panel kept empty space, and the text stayed 12.5 px on a 1920×1080 screen. Here:

* the column is zoomed by ``min(width / 1280, height / 720)`` (between 1 and :data:`ZOOM_MAX`), so
  at 1920×1080 the panel and its text are 1.5 times larger and take the same share of the screen;
* the joints' panel is as tall as its content (at most :data:`TOP_MAX` of the column; beyond that it
  scrolls, with a cue), and the views of J get all the rest;
* every scroll area that has more below shows a "more below" band at its bottom;
* on short screens (150 % zoom of a 1280×720 screen leaves 853×480) the panel is zoomed by 0.8 and
  rows are tighter, so the joints and Configuration stay in sight;
* while a motion runs, its numbers (rates, κ, σmin, t, the slow-down) sit in the 3-D view's corner.

Colours here are chosen for at least 4.5:1 on their background (checked by the tests from this text).
"""

from __future__ import annotations

__all__ = [
    "LAYOUT_CSS",
    "LAYOUT_JS",
    "PANEL_WIDTH",
    "COLUMN",
    "ZOOM_MAX",
    "TOP_MAX",
    "TEXT_COLOURS",
    "MIN_TEXT_PX",
    "KEY_TEXT_PX",
]

PANEL_WIDTH = 400
"""Width of the docked panel at zoom 1 [px]: at 1280×720 the 3-D view keeps 69 % of the window."""
COLUMN = PANEL_WIDTH + 4
"""Width viser gives the docked column for :data:`PANEL_WIDTH` (its border included) [px]."""
ZOOM_MAX = 1.6
"""Largest zoom of the panel (at 2048×1152 and beyond)."""
TOP_MAX = 0.62
"""Largest share of the column the joints' panel takes; the views of J keep the rest."""

MIN_TEXT_PX = 12.0
"""Least size of any text on screen [CSS px at 1280×720]. A 3 m wide image of 1280 px has 2.34 mm per px,
the capitals of the page's sans-serif are about 0.72 of its size: 12 px → capitals of 20 mm, which subtend
11.6 arcmin at 6 m and 8.7′ at 8 m (normal vision resolves letters of 5′; 10′ is the usual least size
where reading speed does not matter, 16′ for text that is read). Browser zoom 150 % (tested) makes it
10.4′ at 8 m."""
KEY_TEXT_PX = 17.0
"""Least size of what the room reads at a singularity (the status, the motion's numbers, the words at a
lost direction in the 3-D view) [CSS px at 1280×720]: capitals of 29 mm, 16.4′ at 6 m and 12.3′ at 8 m."""

TEXT_COLOURS = {
    "label": ("#343a40", "#ffffff"),
    "selected tab": ("#1c3c9c", "#ffffff"),
    "tab": ("#343a40", "#ffffff"),
    "hint and description": ("#495057", "#ffffff"),
    "scroll cue": ("#1f2328", "#ffffff"),
    "folder title": ("#1f2328", "#ffffff"),
    "readout head": ("#1f2328", "#f1f3f5"),
    "outlined button": ("#1c3c9c", "#ffffff"),
    "filled button": ("#ffffff", "#3451b2"),
    "chart legend": ("#343a40", "#ffffff"),
    "slowed": ("#8a3b00", "#f1f3f5"),
}
"""(text, background) of what the page shows: field labels (joint sliders' labels have their joint's
shade, see :func:`app.views.palette.joint_text_hex`), tabs, hints, the scroll cue, the motion readout."""

_C = {k: v[0] for k, v in TEXT_COLOURS.items()}

LAYOUT_CSS = f"""
<style>
:root {{ --jl-zoom: 1; }}
/* The column is zoomed (its width in its own units stays viser's); its shadow is widened to match. */
[data-dock-region="right"] {{ zoom: var(--jl-zoom); }}
.jl-shadow {{ width: calc({COLUMN}px * var(--jl-zoom)) !important; }}
/* The split: the joints' panel as tall as its content, the views of J the rest. */
.jl-views {{ flex: 1 1 0px !important; }}
/* A band at the bottom of a scroll area that has more below. */
.jl-more {{ position: relative; }}
.jl-more::after {{ content: "▾ more below: scroll"; position: absolute; left: 0; right: 12px; bottom: 0;
  padding: 14px 0 2px 0; text-align: center; font-size: 13px; font-weight: 700; color: {_C["scroll cue"]};
  background: linear-gradient(rgba(255,255,255,0), #ffffff 60%); pointer-events: none; z-index: 3; }}
/* Legible from the back: labels, tabs and hints dark enough (≥ 4.5:1). */
label, .mantine-InputWrapper-label {{ color: {_C["label"]}; }}
.mantine-InputWrapper-description, .mantine-Slider-markLabel {{ color: {_C["hint and description"]}; }}
.mantine-Slider-markLabel {{ font-size: {MIN_TEXT_PX:g}px !important; }}  /* Mantine's 8.9 px */
.mantine-Button-label {{ font-size: max(1em, {MIN_TEXT_PX:g}px); }}  /* compact buttons: 11.1 px */
/* The joint values and the menus: 11.1 px in viser's compact inputs, whose height is in em: the box
   keeps its height (1.875 × 11.1 px), the text in it is 12 px. */
.mantine-Input-input {{ font-size: {MIN_TEXT_PX:g}px !important; min-height: 0 !important;
  height: 20.8px !important; padding-top: 0 !important; padding-bottom: 0 !important;
  line-height: 20px !important; }}
.mantine-Select-option {{ font-size: max(1em, {MIN_TEXT_PX:g}px) !important; }}
.u-legend {{ font-size: {MIN_TEXT_PX:g}px !important; color: {_C["chart legend"]} !important; }}
.u-legend .u-value {{ color: {_C["chart legend"]} !important; }}  /* uPlot's 10.4 px, grey values 3.3:1 */
.u-legend.u-inline {{ white-space: normal !important; }}  /* the legend wraps: q̇₆ was cut at the right */
.u-legend.u-inline tr {{ white-space: nowrap; }}
/* Lines of text keep clear of the scroll bar at the column's right edge (they ran under it). */
.jl-sub, .jl-warn, .jl-note {{ padding-right: 10px; }}
/* The first hint goes while J is enlarged (it sat on the enlarged J's lower edge). */
body:has(.mantine-Modal-root .jl-big) .jl-hint {{ display: none; }}
/* Filled buttons (Enlarge J, Record a demo, Upload): white on Mantine's #617be2 was 3.86:1. */
.mantine-Button-root:not([data-variant]):not(:disabled) {{
  background: {TEXT_COLOURS["filled button"][1]} !important; color: {_C["filled button"]} !important; }}
.mantine-Button-root:not([data-variant]):not(:disabled):hover {{ background: #2a4396 !important; }}
[data-dock-tab][role="tab"] {{ color: {_C["tab"]} !important; padding: 0 0.5em !important;
  height: 2.2em !important; opacity: 1 !important; }}  /* viser fades unselected tabs to 0.65: 4.04:1 */
[data-dock-tab][role="tab"][aria-selected="true"] {{ color: {_C["selected tab"]} !important; font-weight: 700;
  box-shadow: inset 0 -3px 0 0 {_C["selected tab"]} !important; }}
.mantine-Button-root[data-variant="outline"] {{ color: {_C["outlined button"]} !important;
  border-color: {_C["outlined button"]} !important; }}  /* Play, Pause, …: Mantine's #617be2 is 3.86:1 */
[data-dock-tab][role="tab"] > div:first-child {{ margin-right: 0.3em !important; }}
.mantine-Paper-root legend, .mantine-Paper-root .mantine-Text-root {{ color: {_C["folder title"]}; }}
.jl sub, .jl sup {{ font-size: max(0.9em, 12px); }}  /* no text under 12 px (10′ at 6 m, see docs) */
[data-dock-region] .jl-mathml {{ overflow-x: auto; }}
/* The enlarged J leaves the panel free: its sliders move J while it is watched. */
.mantine-Modal-root:has(.jl-big) .mantine-Modal-overlay, .mantine-Modal-inner:has(.jl-big) {{
  right: calc({COLUMN}px * var(--jl-zoom)) !important; width: auto !important; }}
.mantine-Modal-inner:has(.jl-big) .mantine-Modal-content {{
  max-width: calc(100vw - {COLUMN}px * var(--jl-zoom) - 24px) !important; }}
/* The motion's numbers in the 3-D view's top-left corner, beside the arm (out of the panel's flow, so
   the sliders and Configuration stay where they are). The 3-D labels keep out of it: its sizes here are
   app.views.panel.live_box's. */
.jl-live {{ position: fixed; left: 12px; top: 12px; width: 350px; z-index: 20; background: #f1f3f5;
  border: 1px solid #adb5bd; border-radius: 8px; padding: 4px 8px; box-shadow: 0 1px 6px rgba(0,0,0,.15); }}
.jl-live-head {{ display: flex; gap: 14px; font-size: 16px; color: {_C["readout head"]};
  font-variant-numeric: tabular-nums; }}
.jl-live-head b {{ font-size: 18px; }}
.jl-live-rates {{ display: grid; grid-template-columns: repeat(3, 1fr); gap: 0 10px;
  font-variant-numeric: tabular-nums; }}
.jl-live-rate {{ display: flex; align-items: baseline; gap: 4px; font-size: 15px; font-weight: 700; }}
.jl-live-rate b {{ margin-left: auto; font-size: 18px; }}
.jl-live-rate small {{ font-size: 12px; font-weight: 600; }}
.jl-live-foot {{ font-size: 13px; color: {_C["readout head"]}; }}
.jl-live-slow {{ color: {_C["slowed"]}; font-weight: 700; }}
/* The status's lines while a motion is on screen (the lost direction, why it stopped): under the rates. */
.jl-live-lines {{ border-top: 1px solid #dee2e6; margin-top: 3px; padding-top: 3px; }}
.jl-live-lines .jl-sub {{ margin: 0 0 2px 0; }}
@media (max-height: 600px) {{
  .mantine-Slider-root {{ min-height: 1.4em !important; }}
  .jl-status {{ font-size: 16px !important; padding: 0.15em 0.5em !important;
    margin-bottom: 4px !important; }}
  [data-dock-tab][role="tab"] {{ height: 1.9em !important; }}
}}
</style>
"""

LAYOUT_JS = """
(() => {
  if (window.__jacobianLabLayout) return;
  window.__jacobianLabLayout = true;
  // Larger on large screens; on short ones (150 % zoom of 1280×720 leaves 480 px) a little smaller, so
  // the joints and Configuration stay in sight above the views of J.
  const zoomFor = () => {
    // Not on a touch screen (a phone held sideways): its text would fall under 12 px.
    const touch = matchMedia("(pointer: coarse)").matches;
    if (innerHeight < 600) return touch ? 1 : Math.max(0.8, Math.floor(innerHeight / 600 * 20) / 20);
    const z = Math.min(innerWidth / 1280, innerHeight / 720);
    return Math.min(__ZOOM_MAX__, Math.max(1, Math.floor(z * 20) / 20));
  };
  const tag = () => {
    const column = document.querySelector('[data-dock-region="right"]');
    if (!column) return;
    for (const d of document.querySelectorAll('div[style*="width: __COLUMN__px"]')) {
      const shadow = d !== column && !column.contains(d) && d.style.position === "absolute";
      if (shadow) d.classList.add("jl-shadow");
    }
    // viser's two panel cells (its flex, or once React re-rendered over ours its grow and our basis).
    const cells = [...column.querySelectorAll("div")].filter(
      (d) => d.style && d.style.minHeight === "50px" && (d.style.flex || d.style.flexBasis));
    const top = cells.find((c) => c.querySelector(".jl-status"));
    if (!top) return;  // not drawn yet: tagging now would mark the joints' cell as a view for good
    for (const c of cells) {
      c.classList.toggle("jl-top", c === top);
      c.classList.toggle("jl-views", c !== top);
    }
    // The joints' panel as tall as its content (its header plus what it scrolls), at most TOP_MAX.
    const viewport = top && top.querySelector(".mantine-ScrollArea-viewport");
    if (viewport) {
      const inner = viewport.firstElementChild || viewport;
      const content = inner.scrollHeight;
      const chrome = top.offsetHeight - viewport.clientHeight;
      const want = Math.round(Math.min(chrome + content + 2, __TOP_MAX__ * column.clientHeight));
      // Set again when React gave the cell its own grow back (a panel built again in another language):
      // with a grow of 0.5 the joints' panel took half the column, the views of J cut below it.
      const grown = top.style.getPropertyValue("flex-grow") !== "0";
      if (grown || Math.abs(top.offsetHeight - want) > 1) {
        top.style.setProperty("flex", `0 0 ${want}px`, "important");
      }
    }
  };
  const cue = () => {
    for (const viewport of document.querySelectorAll('[data-dock-region] .mantine-ScrollArea-viewport')) {
      const root = viewport.parentElement;
      if (!root) continue;
      const more = viewport.clientHeight > 0 &&
        viewport.scrollTop + viewport.clientHeight < viewport.scrollHeight - 4;
      root.classList.toggle("jl-more", more);
    }
  };
  // The classroom box folds to its title line once the tab presents or follows (title "Classroom · …"),
  // once per role: a teacher or student who opens it again keeps it open. A request to hand over
  // ("Classroom — …") unfolds it: the presenter must see the two buttons. In the docked column and in a
  // phone's bottom sheet alike (only a folder's head whose title names the box is touched).
  const fold = () => {
    for (const head of document.querySelectorAll('div[style*="cursor: pointer"]')) {
      const title = head.textContent.trim();
      const role = title.split(":")[0];  // "Classroom · presenting", not the number of followers
      const words = window.__jacobianLabClassroomWords || ["Classroom"];
      if (words.some((w) => title.startsWith(w + " —"))) {
        const body = head.nextElementSibling;
        const shut = body && body.getAttribute("aria-hidden") === "true";
        if (head.dataset.jlFolded !== role && shut) head.click();
        head.dataset.jlFolded = role;
        continue;
      }
      if (!words.some((w) => title.startsWith(w + " ·")) || head.dataset.jlFolded === role) continue;
      head.dataset.jlFolded = role;
      const body = head.nextElementSibling;
      if (body && body.getAttribute("aria-hidden") === "false") head.click();
    }
  };
  // A symbolic J wider than its box is set smaller to fit (down to 11 px); beyond that it scrolls.
  const fit = () => {
    for (const box of document.querySelectorAll('[data-dock-region] .jl-mathml')) {
      const key = `${box.innerHTML.length}:${box.clientWidth}`;
      if (box.clientWidth === 0 || box.dataset.jlFit === key) continue;
      box.style.fontSize = "";
      const size = parseFloat(getComputedStyle(box).fontSize);
      if (box.scrollWidth > box.clientWidth + 1) {
        box.style.fontSize = `${Math.max(11, (size * box.clientWidth) / box.scrollWidth - 0.2)}px`;
      }
      box.dataset.jlFit = key;
    }
  };
  const apply = () => {
    document.documentElement.style.setProperty("--jl-zoom", String(zoomFor()));
    tag();
    fold();
    fit();
    cue();
  };
  apply();
  addEventListener("resize", apply);
  document.addEventListener("scroll", cue, true);
  setInterval(apply, 400);
})();
"""
for _key, _value in (("__ZOOM_MAX__", ZOOM_MAX), ("__TOP_MAX__", TOP_MAX), ("__COLUMN__", COLUMN)):
    LAYOUT_JS = LAYOUT_JS.replace(_key, str(_value))
