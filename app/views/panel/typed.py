"""What a number box of the page accepts, said in words (a page script).

viser's slider boxes are Mantine number inputs: they drop every character that is not a digit, a
point or a minus, silently (``1e-3`` typed key by key became −13, a pasted ``0,3`` became 3). This
script stops those keys and pastes before the box sees them and says why next to the box; a pasted
number in exponent form (``1e-3``) is written out (``0.001``). The Build tab's fields are text boxes
read by :mod:`app.core.numbers`, which refuses in words on the server.
"""

from __future__ import annotations

import json

from ...core.i18n import N_, Translator, translations

__all__ = ["NUMBER_GUARD_JS", "number_guard_js", "SAID"]

SAID = {
    "written": N_("{text} written as {number}."),
    "not_number": N_("“{text}” is not a number: nothing was changed."),
    "exponent": N_("“{text}”: keep typing the exponent; Enter (or a pause) writes it as a plain decimal."),
    "dropped": N_("Exponent dropped."),
    "not_exponent": N_("“{key}” is not part of an exponent."),
    "point": N_("Use a point for decimals: 0.3, not 0,3."),
    "first": N_("Type the number before its exponent (1e-3)."),
    "sign": N_("A sign goes first: −0.5, not 0.5−."),
    "not_part": N_("“{key}” is not part of a number."),
    "paste_point": N_("“{text}”: use a point for decimals ({fixed})"),
    "too_large": N_("“{text}” is too large to be a number here."),
    "not_a_number": N_("“{text}” is not a number."),
}
"""What the guard says, in English; :func:`number_guard_js` gives the page the tab's language's words."""

NUMBER_GUARD_JS = r"""
(() => {
  const SAID = __SAID__;
  const said = (key, fields) =>
    window.__jacobianLabSaid[key].replace(/\{(\w+)\}/g, (m, k) => (k in fields ? fields[k] : m));
  window.__jacobianLabSaid = SAID;  // a rebuilt panel (another language) gives the guard its new words
  if (window.__jacobianLabNumberGuard) return;
  window.__jacobianLabNumberGuard = true;
  const PLAIN = /^\s*[+\-]?(\d+\.?\d*|\.\d+)\s*$/;
  const NUMBER = /^\s*[+\-\u2212]?(\d+\.?\d*|\.\d+)([eE][+\-\u2212]?\d+)?\s*$/;
  const COMMA = /^\s*[+\-\u2212]?\d*,\d+\s*$/;
  const isNumberBox = (el) =>
    el && el.tagName === "INPUT" && el.closest(".mantine-NumberInput-root") !== null;
  let tip = null;
  let timer = 0;
  const say = (el, text) => {
    if (tip === null) {
      tip = document.createElement("div");
      tip.id = "jl-typed-tip";
      tip.setAttribute("role", "alert");
      document.body.appendChild(tip);
    }
    tip.textContent = text;
    const r = el.getBoundingClientRect();
    const left = Math.max(4, Math.min(r.right - 280, window.innerWidth - 290));
    const below = r.bottom + 70 < window.innerHeight;  // else above the box
    const where = below ? `top:${r.bottom + 4}px` : `bottom:${window.innerHeight - r.top + 4}px`;
    tip.style.cssText =
      `position:fixed;z-index:10000;left:${left}px;${where};width:280px;` +
      "background:#fff4f4;color:#96001a;border:1px solid #96001a;border-radius:4px;" +
      "padding:4px 6px;font:13px/1.35 system-ui,sans-serif;display:block";
    clearTimeout(timer);
    timer = setTimeout(() => { tip.style.display = "none"; }, 6000);
  };
  const written = (x) => {
    const t = x.toFixed(10).replace(/\.?0+$/, "");
    return t === "-0" ? "0" : t;
  };
  const put = (el, text) => {
    const setter = Object.getOwnPropertyDescriptor(HTMLInputElement.prototype, "value").set;
    setter.call(el, text);
    el.dispatchEvent(new Event("input", { bubbles: true }));
  };
  // Exponent form typed key by key ("1e-3"): held here, shown in the tip, and written out as a
  // plain decimal on Enter, Tab, leaving the box or a pause (the box itself would drop the "e").
  let pending = null, pendingBox = null, pendingTimer = 0;
  const commit = () => {
    clearTimeout(pendingTimer);
    if (pending === null) return;
    const text = pending, el = pendingBox;
    pending = null;
    const x = Number(text.replace("\u2212", "-"));
    if (NUMBER.test(text) && Number.isFinite(x) && Math.abs(x) < 1e12) {
      put(el, written(x));
      say(el, said("written", {text, number: written(x)}));
    } else {
      say(el, said("not_number", {text}));
    }
  };
  const hold = (el, text) => {
    pending = text;
    pendingBox = el;
    say(el, said("exponent", {text}));
    clearTimeout(pendingTimer);
    pendingTimer = setTimeout(commit, 1500);
  };
  document.addEventListener("focusout", (ev) => { if (ev.target === pendingBox) commit(); }, true);
  document.addEventListener("keydown", (ev) => {
    const el = ev.target;
    if (!isNumberBox(el) || ev.ctrlKey || ev.metaKey || ev.altKey) return;
    if (pending !== null && el === pendingBox) {
      if (ev.key === "Enter" || ev.key === "Tab") {
        commit();
        if (ev.key === "Enter") ev.preventDefault();
        return;
      }
      if (ev.key === "Escape") { pending = null; ev.preventDefault(); say(el, said("dropped", {})); return; }
      if (ev.key === "Backspace") {
        ev.preventDefault();
        const shorter = pending.slice(0, -1);
        if (/[eE]/.test(shorter)) hold(el, shorter); else { pending = null; say(el, said("dropped", {})); }
        return;
      }
      if (ev.key.length === 1) {
        ev.preventDefault();
        ev.stopPropagation();
        if (/[0-9+\-]/.test(ev.key)) hold(el, pending + ev.key);
        else say(el, said("not_exponent", {key: ev.key}));
      }
      return;
    }
    if (ev.key.length !== 1) return;
    if (ev.key === ",") {
      ev.preventDefault();
      say(el, said("point", {}));
    } else if (ev.key === "e" || ev.key === "E") {
      ev.preventDefault();
      if (PLAIN.test(el.value) && el.value.trim() !== "") hold(el, el.value.trim() + "e");
      else say(el, said("first", {}));
    } else if ((ev.key === "-" || ev.key === "+") && (el.selectionStart || 0) > 0) {
      ev.preventDefault();
      say(el, said("sign", {}));
    } else if (!/[0-9.\-+]/.test(ev.key)) {
      ev.preventDefault();
      say(el, said("not_part", {key: ev.key}));
    }
  }, true);
  document.addEventListener("paste", (ev) => {
    const el = ev.target;
    if (!isNumberBox(el)) return;
    const text = (ev.clipboardData || window.clipboardData).getData("text");
    if (PLAIN.test(text)) return;
    ev.preventDefault();
    ev.stopPropagation();  // the box's own paste handler would insert a mangled copy
    const shown = text.trim().slice(0, 30);
    if (COMMA.test(text)) {
      say(el, said("paste_point", {text: shown, fixed: shown.replace(",", ".")}));
    } else if (NUMBER.test(text)) {
      const x = Number(text.trim().replace("\u2212", "-"));
      if (Number.isFinite(x) && Math.abs(x) < 1e12) put(el, written(x));
      else say(el, said("too_large", {text: shown}));
    } else {
      say(el, said("not_a_number", {text: shown}));
    }
  }, true);
})();
"""


def number_guard_js(tr: Translator | None = None) -> str:
    """The guard's script, saying its words in ``tr``'s language (a JSON object: no translation can end
    a string of the script)."""
    _ = (tr or translations()).gettext
    words = json.dumps({key: _(text) for key, text in SAID.items()}, ensure_ascii=False)
    return NUMBER_GUARD_JS.replace("__SAID__", words.replace("</", "<\\/"))
