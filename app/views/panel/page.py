"""The page script that keeps a tab's robot, q, open tab and chosen language in the page's address (its
query string, ``?robot=puma560&q=0,0.5,…&tab=Motion&lang=pt``: never the fragment, which breaks
viser's reconnection), and a presenter's reconnect key in the browser's local storage, and reports
them on every (re)connection.

The server never sees the page's address (viser), so the script writes a JSON report into a hidden
text input of the panel (``report``): ``{"kind": "load", "address": …, "resume": …, "tab": …,
"languages": navigator.languages}`` when the page (re)connects (a reload, a server restart: viser
reconnects the same page and the script runs again) and ``{"kind": "tab", "tab": …}`` when the
user opens a tab, and ``{"kind": "view", "width": …, "height": …, "touch": …}`` (the window, where the
tab's labels are placed) after the load report, when the window is resized and when the panel is built
again in another language (a report sent into the old panel's input is lost). The server reads it as
hostile input (:func:`app.core.page_state.parse_report`).
The server calls ``window.__jacobianLabPage.address(text)``, ``.remember(key)`` and
``.showTab(label)`` back.
The script also says in words when the connection to the lab is lost (viser shows no message).
"""

from __future__ import annotations

import json

from ...core.i18n import N_

__all__ = ["page_js", "STORAGE_KEY", "LOST_WORDS"]

STORAGE_KEY = "jacobianLab.presenterKey"
LOST_WORDS = N_("Connection to the lab lost: trying to reconnect… (what you see is not live).")

_JS = r"""
(() => {
  const REPORT = %(report)s, STORAGE = %(storage)s, LOST = %(lost)s, LOAD = %(load)s;
  const w = window;
  // read before anything rewrites it; a presenter link's token is kept for the token box's script
  // (app.views.panel.classroom) and never reported nor left in the address bar
  const first = new URLSearchParams(location.search);
  if (first.has("presenter")) {
    w.__jacobianLabPresenter = first.get("presenter");
    first.delete("presenter");
    const rest = first.toString();
    history.replaceState(null, "", location.pathname + (rest ? "?" + rest : ""));
  }
  const initial = first.toString();
  let reported = false;  // the server's address is taken only after the page has told its own
  const findInput = () => {
    const label = document.querySelector(`label[for="${REPORT}"]`);
    if (!label) return null;
    const row = label.closest(".mantine-Flex-root");
    const box = row ? row.parentElement : null;
    if (box) box.style.display = "none";  // a channel, not a field
    return row ? row.querySelector("input") : null;
  };
  let count = 0;
  const send = (report) => {
    const input = findInput();
    if (!input) return false;
    count += 1;
    report.n = count;
    const setter = Object.getOwnPropertyDescriptor(HTMLInputElement.prototype, "value").set;
    setter.call(input, JSON.stringify(report));
    input.dispatchEvent(new Event("input", { bubbles: true }));
    return true;
  };
  // The query string, never the fragment: viser's client opens its websocket at the page's
  // address minus the query, and a WebSocket address with a fragment is refused (no reconnection).
  const fields = () => new URLSearchParams(location.search);
  const write = (f) => {
    const text = f.toString().replace(/%%2C/g, ",");
    history.replaceState(null, "", location.pathname + (text ? "?" + text : ""));
  };
  const setField = (name, value) => {
    const f = fields();
    if (value) f.set(name, value); else f.delete(name);
    write(f);
  };
  const tabs = () => Array.from(document.querySelectorAll("[role=tab]"));
  const showTab = (label) => {
    const t = tabs().find((b) => b.textContent.trim() === label);
    if (t && t.getAttribute("aria-selected") !== "true") {
      // viser's dock tabs select on the pointer going down, not on a click alone.
      for (const type of ["pointerdown", "mousedown", "pointerup", "mouseup", "click"]) {
        const Event_ = type.startsWith("pointer") ? PointerEvent : MouseEvent;
        t.dispatchEvent(new Event_(type, { bubbles: true, cancelable: true, button: 0 }));
      }
    }
    return Boolean(t);
  };
  const api = {
    address: (text) => {  // robot and q from the server; the tab stays the page's
      if (!reported) return;
      const f = new URLSearchParams(text), tab = fields().get("tab");
      if (tab) f.set("tab", tab);
      write(f);
    },
    remember: (key) => {
      try { if (key) localStorage.setItem(STORAGE, key); else localStorage.removeItem(STORAGE); }
      catch (e) { /* storage refused: a reload then needs the token again */ }
    },
    showTab: (label) => {
      // Kept for 4 s: the panel may redraw its tabs as the restored robot arrives.
      let tries = 0;
      const go = () => { showTab(label); if (++tries < 20) setTimeout(go, 200); };
      go();
    },
  };
  w.__jacobianLabPage = api;
  if (!w.__jacobianLabTabWatch) {  // once per page: tab clicks are reported and kept in the address
    w.__jacobianLabTabWatch = true;
    const opened = (ev) => {
      const t = ev.target.closest && ev.target.closest("[role=tab]");
      if (!t) return;
      const label = t.textContent.trim();  // the clicked tab (it is selected after this event)
      setField("tab", label);
      w.__jacobianLabSend && w.__jacobianLabSend({ kind: "tab", tab: label });
    };
    document.addEventListener("click", opened, true);
    // The arrow keys (and Home, End) select a tab without a click: the focused one is the open one.
    document.addEventListener("keyup", (ev) => {
      if (/^(Arrow|Home$|End$)/.test(ev.key)) opened(ev);
    }, true);
  }
  w.__jacobianLabSend = send;
  // The window's size (the 3-D view's canvas and the panel follow it): on load and when it changes.
  const sendView = () => send({ kind: "view", width: w.innerWidth, height: w.innerHeight,
    touch: Boolean(w.matchMedia && w.matchMedia("(pointer: coarse)").matches) });
  if (!w.__jacobianLabViewWatch) {
    let timer = 0;
    w.__jacobianLabViewWatch = true;
    w.addEventListener("resize", () => {
      clearTimeout(timer);
      timer = setTimeout(() => w.__jacobianLabSendView && w.__jacobianLabSendView(), 150);
    });
  }
  w.__jacobianLabSendView = sendView;
  // Connection lost, in words: viser's client shows no message when its websocket drops. Its
  // connection state is not reachable from the page; the server's tab beats (see app.tab.page).
  w.__jacobianLabBeat = Date.now();
  if (!w.__jacobianLabLostWatch) {
    w.__jacobianLabLostWatch = setInterval(() => {
      let banner = document.getElementById("jl-connection-lost");
      const lost = Date.now() - w.__jacobianLabBeat > 7000;
      if (lost && !banner) {
        banner = document.createElement("div");
        banner.id = "jl-connection-lost";
        banner.setAttribute("role", "alert");
        banner.textContent = LOST;
        banner.style.cssText = "position:fixed;top:0;left:0;right:0;z-index:10001;padding:8px 12px;" +
          "background:#96001a;color:#fff;font:600 16px/1.3 system-ui,sans-serif;text-align:center";
        document.body.appendChild(banner);
      } else if (!lost && banner) banner.remove();
    }, 1000);
  }
  // The report of this (re)connection: the address, the kept key and the open tab.
  let tries = 0;
  const report = () => {
    if (!LOAD) {  // the panel built again (another language): no report, but its channel is hidden too,
      reported = true;  // and the window told again through it (a report sent as the panel was rebuilt,
      // the window's right after a load that asks for another language, is lost with the old channel)
      const hide = () => { if (!sendView() && ++tries < 100) setTimeout(hide, 100); };
      hide();
      return;
    }
    const f = new URLSearchParams(initial);
    const ok = send({
      kind: "load",
      address: initial,
      resume: (() => { try { return localStorage.getItem(STORAGE) || ""; } catch (e) { return ""; } })(),
      tab: "",
      languages: Array.from(navigator.languages || [navigator.language || ""]).slice(0, 16),
    });
    if (!ok && ++tries < 100) { setTimeout(report, 100); return; }
    reported = true;
    sendView();
    if (ok && f.get("tab")) api.showTab(f.get("tab"));
  };
  report();
})();
"""


def page_js(report_uuid: str, lost: str = LOST_WORDS, report: bool = True) -> str:
    """The page script of one tab whose hidden report input has DOM label ``report_uuid``; ``lost``:
    the words for a lost connection, in the tab's language; ``report``: report the address (a
    (re)connection; not when the panel is only built again in another language). Every value is
    passed as a JSON literal, never as code."""
    return _JS % {
        "load": json.dumps(report),
        "report": json.dumps(report_uuid),
        "storage": json.dumps(STORAGE_KEY),
        "lost": json.dumps(lost),
    }
