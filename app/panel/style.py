"""CSS for the panel: projector-sized readouts, the matrix, bars, and joint-coloured sliders.

viser renders ``add_html`` content as raw HTML, so a ``<style>`` element
added once per client styles the whole page. Our own HTML uses ``jl-``
classes; sliders are coloured through the ``id`` viser gives their root
element (the handle's uuid) and their label's ``for`` attribute.
"""

from __future__ import annotations

__all__ = ["BASE_CSS", "slider_css", "SLIDER_KEYS_JS"]

BASE_CSS = """
<style>
.jl { font-size: 15px; line-height: 1.35; color: #1f2328; }
.jl-status { display: flex; align-items: center; gap: 0.6em; padding: 0.35em 0.6em; border-radius: 8px;
  color: white; font-weight: 700; font-size: 19px; letter-spacing: 0.2px; }
.jl-status small { font-weight: 500; font-size: 14px; opacity: 0.95; }
.jl-table { border-collapse: collapse; width: 100%; }
.jl-table td, .jl-table th { padding: 2px 4px; vertical-align: baseline; }
.jl-table th { text-align: left; font-weight: 500; color: #555; }
.jl-table td.v { text-align: right; font-variant-numeric: tabular-nums; font-weight: 650;
  white-space: nowrap; }
.jl-table td.v.wrap { white-space: normal; }
.jl-note { color: #666; font-size: 13px; }
.jl-matrix { border-collapse: collapse; margin: 4px auto; font-variant-numeric: tabular-nums; font-size: 14px;
  font-family: "DejaVu Sans Mono", "Menlo", "Consolas", monospace; }
.jl-matrix td, .jl-matrix th { padding: 2px 5px; text-align: right; white-space: nowrap; }
.jl-matrix th.col { text-align: center; font-family: inherit; font-weight: 700; border-bottom: 3px solid; }
.jl-matrix th.row { text-align: left; font-weight: 600; color: #333; padding-right: 10px; }
.jl-matrix tr.off td, .jl-matrix tr.off th.row { color: #aaa; }
.jl-matrix tr.split td, .jl-matrix tr.split th { border-top: 1px solid #ccc; }
.jl-matrix-wrap { overflow-x: auto; padding-bottom: 4px; }
.jl-big .jl-matrix { font-size: 26px; }
.jl-big .jl-matrix td, .jl-big .jl-matrix th { padding: 4px 14px; }
.jl-mathml { overflow-x: auto; padding: 4px 0; font-size: 17px; }
.jl-big .jl-mathml { font-size: 24px; }
.jl-bars { width: 100%; border-collapse: collapse; }
.jl-bars td { padding: 2px 3px; font-variant-numeric: tabular-nums; white-space: nowrap; }
.jl-bars td.name { font-weight: 700; width: 3.2em; }
.jl-bars td.track { width: 100%; position: relative; }
.jl-bars td.val { text-align: right; width: 6.5em; font-weight: 600; }
.jl-bar-bg { position: relative; height: 14px; background: #eef0f3; border-radius: 3px; }
.jl-bar-mid { position: absolute; left: 50%; top: -2px; bottom: -2px; width: 1px; background: #999; }
.jl-bar { position: absolute; top: 0; height: 14px; border-radius: 3px; }
.jl-bar.over {
  background-image: repeating-linear-gradient(45deg, transparent 0 5px, rgba(255,255,255,.55) 5px 9px); }
.jl-twist { font-variant-numeric: tabular-nums; }
/* The projector view of J: a modal as wide as the screen allows. */
.mantine-Modal-inner:has(.jl-big) .mantine-Modal-content { flex: 0 0 auto; width: auto; max-width: 96vw; }
.mantine-Modal-inner:has(.jl-big) .mantine-Modal-title { font-size: 22px; font-weight: 700; }
</style>
"""


def slider_css(uuid: str, color: str) -> str:
    """CSS rules colouring the slider whose root has id ``uuid`` (bar, thumb and label) in ``color``."""
    return (
        f'[id="{uuid}"] .mantine-Slider-bar {{ background: {color} !important; }}\n'
        f'[id="{uuid}"] .mantine-Slider-thumb {{ background: {color} !important; }}\n'
        f'label[for="{uuid}"] {{ color: {color}; font-weight: 700; }}\n'
    )


SLIDER_KEYS_JS = """
if (!window.__jacobianLabSliderKeys) {
  window.__jacobianLabSliderKeys = true;
  document.body.addEventListener("keydown", (event) => {
    const target = event.target;
    if (event.key.startsWith("Arrow") && target instanceof Element && target.closest('[role="slider"]')) {
      event.stopPropagation();
    }
  });
}
"""
"""Keeps arrow keys on a focused slider from also orbiting the camera.

viser's keyboard camera controls listen on ``document`` and ignore only
input, textarea and select elements, not Mantine's slider thumbs. This
listener on ``body`` (reached after the slider's own handler, before
``document``) stops the event there.
"""
