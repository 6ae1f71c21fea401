"""What speaking Polish costs a redraw of the J(q) tab's readouts (status, measures, J matrix) against
English, in CPU time (the best of 7 rounds of 500): `PYTHONPATH=. python bench/bench_i18n_readouts.py`.

On the shared 2-core machine (4 December 2026): English 63 µs, Polish 70 µs (×1.11) with the decimal
comma written by one string replacement (Translator.decimal); ×3.12 (194 µs against 62 µs) with Babel's
format_decimal called per number (the first version).
"""

from __future__ import annotations

import time

import robots
from app.core.i18n import translations
from app.core.snapshot import compute
from app.core.state import LabState
from app.views.panel.matrix import matrix_html
from app.views.panel.readouts import _status_html, measures_html


def main(rounds: int = 7, repeat: int = 500) -> dict[str, float]:
    """The best CPU time per redraw of the readouts [µs], by language code."""
    robot = robots.load("puma560")
    wrist = next(c for c in robot.configurations if c.name == "wrist_singular")
    state = LabState.initial("puma560", robot).replace(q=wrist.q, configuration=wrist.name)
    snap = compute(state)
    best = {"en": float("inf"), "pl": float("inf")}
    for _ in range(rounds):
        for code in best:
            tr = translations(code)
            start = time.process_time()
            for _ in range(repeat):
                _status_html(snap, state, tr)
                measures_html(snap, robot, tr)
                matrix_html(snap.J_shown, robot, snap.rows, "base", tr=tr)
            best[code] = min(best[code], (time.process_time() - start) / repeat * 1e6)
    return best


if __name__ == "__main__":
    best = main()
    print({k: f"{v:.0f} µs" for k, v in best.items()}, f"pl/en = {best['pl'] / best['en']:.2f}")
