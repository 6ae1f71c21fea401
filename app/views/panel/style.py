"""CSS and the page script: projector-sized readouts, the matrix, bars, joint-coloured sliders, keys.

viser renders ``add_html`` content as raw HTML, so a ``<style>`` element
added once per tab styles the whole page. Our own HTML uses ``jl-``
classes; sliders are coloured through the ``id`` viser gives their root
element (the handle's uuid) and their label's ``for`` attribute.
"""

from __future__ import annotations

from ...core.i18n import LANGUAGES, N_, translations
from ..palette import STATUS_TEXT, joint_hex, joint_text_hex

__all__ = ["BASE_CSS", "slider_css", "PAGE_JS", "PAGE_TITLE", "steps_js"]

PAGE_TITLE = "Jacobian Lab"

BASE_CSS = """
<style>
.jl { font-size: 14px; line-height: 1.35; color: #1f2328; }
.jl-status { display: flex; align-items: center; gap: 0.5em; padding: 0.3em 0.6em; border-radius: 8px;
  font-weight: 700; font-size: 18px; letter-spacing: 0.2px; margin-bottom: 7px; }
.jl-status small { font-weight: 600; font-size: 14px; }
.jl-sub { color: #3d434b; font-size: 13px; margin: -4px 0 6px 0; overflow-wrap: anywhere; }
.jl-desc { display: -webkit-box; -webkit-line-clamp: 2; -webkit-box-orient: vertical; overflow: hidden;
  line-height: 1.2; margin-bottom: 2px; cursor: pointer; }
.jl-desc-all:checked + .jl-desc { -webkit-line-clamp: unset; }
.jl-lines { min-height: 29px; display: flow-root; }  /* flow-root: its lines' margins stay inside, so its
  top does not move as they come and go; while a motion is on screen ("jl-held") the page script holds its height */
/* The first hint: one line over the 3-D view's lower edge (out of the panel's flow: no slider moves). The 3-D
   labels keep out of it: its sizes here are app.views.panel.hint_box's. */
.jl-hint { position: fixed; left: 72px; bottom: 14px; max-width: min(640px, calc(100vw - 500px)); z-index: 20;
  color: #1f3a93; background: #eef2ff; font-size: 15px; border: 1px solid #8ea2e6; border-radius: 8px;
  padding: 4px 10px; box-shadow: 0 1px 6px rgba(0,0,0,.15); }
.jl-table { border-collapse: collapse; width: 100%; }
.jl-table td, .jl-table th { padding: 1px 4px; vertical-align: baseline; }
.jl-table th { text-align: left; font-weight: 500; color: #3d434b; }
.jl-table td.v { text-align: right; font-variant-numeric: tabular-nums; font-weight: 650; white-space: nowrap; }
.jl-table td.v.wrap { white-space: normal; }
.jl-note { color: #4f5660; font-size: 12.5px; }
.jl-matrix { border-collapse: collapse; margin: 2px auto; font-variant-numeric: tabular-nums; font-size: 13.5px;
  font-family: "DejaVu Sans Mono", "Menlo", "Consolas", monospace; }
.jl-matrix td, .jl-matrix th { padding: 1px 3px; text-align: right; white-space: nowrap; }
.jl-matrix th.col { text-align: center; font-family: inherit; font-weight: 700; border-bottom: 3px solid; }
.jl-matrix th.row { text-align: left; font-weight: 600; color: #1f2328; padding-right: 6px; }
.jl-matrix tr.off td, .jl-matrix tr.off th.row { color: #5f656e; }
.jl-matrix tr.split td, .jl-matrix tr.split th { border-top: 1px solid #bbb; }
.jl-big .jl-matrix { font-size: 26px; }
.jl-big .jl-matrix td, .jl-big .jl-matrix th { padding: 4px 14px; }
.jl-mathml { padding: 4px 0; font-size: 16px; overflow-wrap: anywhere; }
.jl-big .jl-mathml { font-size: 22px; }
.jl-bars { width: 100%; border-collapse: collapse; }
/* The joint-space map of w: a pixelated heat map, the arm's q as a ring; a click goes there. */
.jl-map { position: relative; width: 100%; max-width: 340px; aspect-ratio: 1; cursor: crosshair;
  margin: 4px auto; }
.jl-map img { width: 100%; height: 100%; image-rendering: pixelated; display: block; border: 1px solid #868e96; }
.jl-map-dot { position: absolute; width: 14px; height: 14px; margin: -7px 0 0 -7px; border-radius: 50%;
  border: 3px solid #fff; box-shadow: 0 0 0 1.5px #000; pointer-events: none; }
.jl-bars td { padding: 1px 3px; font-variant-numeric: tabular-nums; white-space: nowrap; font-size: 13.5px; }
.jl-bars td.name { font-weight: 700; width: 2.4em; }
.jl-bars td.track { width: 100%; position: relative; }
.jl-bars td.val { text-align: right; width: 6.5em; font-weight: 600; }
.jl-bar-bg { position: relative; height: 12px; background: #eef0f3; border-radius: 3px; }
.jl-bar-mid { position: absolute; left: 50%; top: -2px; bottom: -2px; width: 1px; background: #888; }
.jl-bar { position: absolute; top: 0; height: 12px; border-radius: 3px; }
.jl-bar.over {
  background-image: repeating-linear-gradient(45deg, transparent 0 5px, rgba(255,255,255,.6) 5px 9px); }
.jl-vec { border-collapse: collapse; width: 100%; font-variant-numeric: tabular-nums; font-size: 13.5px; }
.jl-vec th { text-align: right; font-weight: 600; color: #3d434b; padding: 1px 4px; }
.jl-vec th.rowname { text-align: left; }
.jl-vec td { text-align: right; padding: 1px 4px; white-space: nowrap; }
.jl-vec tr.lost td { color: #96001a; font-weight: 700; }
.jl-warn { color: #96001a; font-weight: 600; font-size: 13px; }
.jl-erratum { color: #5c3c00; background: #fff4d6; border-left: 3px solid #b8860b; padding: 2px 6px; margin: 4px 0; font-size: 12.5px; }
.jl-conf { margin: 2px 0 0 0; padding-left: 1.1em; font-size: 12.5px; color: #3d434b; }
.jl-conf li { margin: 1px 0; }
.jl-conf b { color: #1f2328; }
.jl-close-row { display: flex; justify-content: flex-end; margin: -8px 0 4px 0; }
.jl-close-x { border: 1px solid #c4c8ce; border-radius: 6px; background: #f4f5f7; font-size: 18px;
  line-height: 1.2; padding: 2px 10px; cursor: pointer; color: #1f2328; }
/* The Derive tab: DH table, one step of a derivation, small 4×4 transforms. */
.jl-dh { border-collapse: collapse; width: 100%; font-size: 13px; font-variant-numeric: tabular-nums; }
.jl-dh th { font-weight: 600; color: #3d434b; border-bottom: 1px solid #bbb; padding: 1px 3px; }
.jl-dh td { text-align: center; padding: 2px 3px; white-space: nowrap; }
.jl-dh tr.sel td { background: #eef2ff; outline: 2px solid #3b5bdb; outline-offset: -2px; }
.jl-step-head { font-weight: 700; font-size: 14px; border-left: 5px solid; padding-left: 6px; margin: 2px 0 4px 0; }
.jl-formula { font-size: 14px; margin: 2px 0 4px 0; color: #1f2328; }
.jl-vec tr.res td, .jl-vec tr.res th { font-weight: 700; color: #1f2328; border-top: 1px solid #ccc; }
.jl-t4s { display: flex; gap: 8px; justify-content: space-between; }
.jl-t4-title { font-size: 12.5px; font-weight: 600; color: #3d434b; text-align: center; }
.jl-br { border-left: 2px solid #555; border-right: 2px solid #555; font-size: 12px; }
/* Slider labels and numbers readable from the back row. */
.mantine-Slider-root { min-height: 1.9em; }
label { font-size: 13px !important; }
/* The projector view of J: a modal as wide as the screen allows. */
.mantine-Modal-inner:has(.jl-big) .mantine-Modal-content { flex: 0 0 auto; width: auto; max-width: 96vw;
  position: relative; }
.mantine-Modal-inner:has(.jl-big) .mantine-Modal-title { font-size: 22px; font-weight: 700; }
</style>
"""


def status_css() -> str:
    """Banner text colours per status (contrast ≥ 4.5:1 on each status colour)."""
    return "".join(
        f'.jl-status[data-status="{status}"] {{ color: {colour}; }}\n'
        for status, colour in STATUS_TEXT.items()
    )


def slider_css(uuid: str, joint: int) -> str:
    """CSS colouring the slider whose root has id ``uuid``: track and thumb in the joint's colour,
    its label in a darker shade of it (contrast ≥ 4.5:1 on white)."""
    color, text = joint_hex(joint), joint_text_hex(joint)
    return (
        f'[id="{uuid}"] .mantine-Slider-bar {{ background: {color} !important; }}\n'
        f'[id="{uuid}"] .mantine-Slider-thumb {{ background: {color} !important; }}\n'
        f'label[for="{uuid}"] {{ color: {text}; font-weight: 700; }}\n'
        # The joint's one name and unit on one line ("q6 wrist swivel [°]"): a wider label box.
        f'div:has(> .mantine-Text-root label[for="{uuid}"]) {{ width: 8.6em !important; }}\n'
    )


PAGE_JS = """
(() => {
  // The split of the right-hand column is app.views.panel.layout's.
  if (window.__jacobianLabKeys) return;
  window.__jacobianLabKeys = true;
  // While a motion plays (and once it stopped) the status's lines are in the readout over the 3-D view
  // and the block under the banner is empty: it keeps the height it had before ("jl-held"), so the
  // sliders and the Play button do not move under the pointer. Set before the page is painted.
  // Each status drawn is a new element: each is looked at once, when it comes.
  let free = null;
  const looked = new WeakSet();
  const hold = () => {
    for (const lines of document.querySelectorAll(".jl-lines")) {
      if (looked.has(lines) || !lines.getClientRects().length) continue;  // seen, or not shown
      looked.add(lines);
      if (!lines.classList.contains("jl-held")) free = lines.getBoundingClientRect().height;
      else if (free !== null) lines.style.minHeight = `${free}px`;
    }
  };
  new MutationObserver(hold).observe(document.body, { childList: true, subtree: true });
  const CLOSE_WORDS = window.__jacobianLabCloseWords || ["Close"];
  const modalClose = () => {
    for (const content of document.querySelectorAll(".mantine-Modal-content")) {
      if (!content.querySelector(".jl-big")) continue;
      for (const button of content.querySelectorAll("button")) {
        if (CLOSE_WORDS.includes(button.textContent.trim())) { button.click(); return true; }
      }
    }
    return false;
  };
  // Arrow keys on a focused slider move it by ten fine steps (Shift: one), never the camera. The
  // value is typed into the slider's own number box, as a user would.
  const STEPS = { ArrowRight: 1, ArrowUp: 1, ArrowLeft: -1, ArrowDown: -1 };
  document.body.addEventListener("keydown", (event) => {
    const target = event.target;
    if (event.key === "Escape" && modalClose()) { event.stopPropagation(); return; }
    if (!(event.key in STEPS) || !(target instanceof Element) || !event.isTrusted) return;
    const thumb = target.closest('[role="slider"]');
    const root = thumb && thumb.closest("[id]");
    const fine = root && (window.__jacobianLabSteps || {})[root.id];
    const input = root && root.parentElement && root.parentElement.querySelector("input.mantine-NumberInput-input");
    if (!fine || !input) return;  // not one of ours: the slider's own keys
    event.preventDefault();
    event.stopPropagation();
    const now = parseFloat(thumb.getAttribute("aria-valuenow"));
    const lo = parseFloat(thumb.getAttribute("aria-valuemin"));
    const hi = parseFloat(thumb.getAttribute("aria-valuemax"));
    const moved = now + STEPS[event.key] * fine * (event.shiftKey ? 1 : 10);
    const value = Math.min(hi, Math.max(lo, Math.round(moved / fine) * fine));
    const decimals = Math.max(0, -Math.floor(Math.log10(fine) + 1e-9));
    const setter = Object.getOwnPropertyDescriptor(HTMLInputElement.prototype, "value").set;
    setter.call(input, value.toFixed(decimals));
    input.dispatchEvent(new Event("input", { bubbles: true }));
    thumb.focus();
    setTimeout(() => thumb.focus(), 0);  // keep the keys on the slider
  }, true);
  document.body.addEventListener("keydown", (event) => {
    if (event.key.startsWith("Arrow") && event.target instanceof Element && event.target.closest('[role="slider"]')) {
      event.stopPropagation();
    }
  });
  // Typing a value into a slider's own number box, as a user would (the server clamps it).
  const typeInto = (id, value) => {
    const root = document.getElementById(id);
    const input = root && root.parentElement && root.parentElement.querySelector("input.mantine-NumberInput-input");
    if (!input) return;
    const fine = (window.__jacobianLabSteps || {})[id] || 0.1;
    const decimals = Math.max(0, -Math.floor(Math.log10(fine) + 1e-9));
    const setter = Object.getOwnPropertyDescriptor(HTMLInputElement.prototype, "value").set;
    setter.call(input, (Math.round(value / fine) * fine).toFixed(decimals));
    input.dispatchEvent(new Event("input", { bubbles: true }));
  };
  // The enlarged J closes with its x, and with a click outside it.
  document.addEventListener("click", (event) => {
    const target = event.target;
    if (!(target instanceof Element)) return;
    const map = target.closest(".jl-map");
    if (map) {  // the joint map: go to the clicked (qi, qj)
      const box = map.getBoundingClientRect();
      const u = Math.min(1, Math.max(0, (event.clientX - box.left) / box.width));
      const v = Math.min(1, Math.max(0, (event.clientY - box.top) / box.height));
      const d = map.dataset;
      typeInto(d.i, parseFloat(d.ilo) + u * (parseFloat(d.ihi) - parseFloat(d.ilo)));
      typeInto(d.j, parseFloat(d.jhi) - v * (parseFloat(d.jhi) - parseFloat(d.jlo)));
      return;
    }
    if (target.closest(".jl-close-x")) { modalClose(); return; }
    if (target.classList.contains("mantine-Modal-inner") || target.classList.contains("mantine-Modal-overlay")) {
      const open = document.querySelector(".mantine-Modal-content .jl-big");
      if (open) modalClose();
    }
  }, true);
})();
"""


CLOSE = N_("Close")
"""The enlarged J's close button (the page script clicks it on Escape, found by its words)."""


def page_js() -> str:
    """The page script (slider keys, closing the enlarged J, clicks on the joint map). The close
    button's words in every language: the script runs once per page, whatever language it speaks."""
    import json

    words = sorted({translations(lang.code).gettext(CLOSE) for lang in LANGUAGES})
    return f"window.__jacobianLabCloseWords = {json.dumps(words)};" + PAGE_JS


def steps_js(steps: dict[str, float]) -> str:
    """A page script registering the fine step of each slider (by DOM id) for the arrow keys."""
    import json

    return (
        f"window.__jacobianLabSteps = Object.assign(window.__jacobianLabSteps || {{}}, {json.dumps(steps)});"
    )
