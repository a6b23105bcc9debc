"""Progress lines for loops over a known number of long items (experiments, training runs).

``Progress(total).line(text)`` counts one more finished item and returns
``"[4/9] <text> (elapsed 3m10s, ETA 4m45s)"``: one whole line per finished item, never a
carriage return, so the output reads the same in a terminal and in a log file. The ETA
assumes the remaining items take as long, on average, as the finished ones.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from attentive_gym._checks import check_int

__all__ = ["Progress", "format_duration"]


def format_duration(seconds: float) -> str:
    """A wall time in seconds as ``"42s"``, ``"3m10s"`` or ``"2h05m"`` (rounded to whole seconds)."""
    total = max(0, round(seconds))
    hours, rest = divmod(total, 3600)
    minutes, secs = divmod(rest, 60)
    if hours:
        return f"{hours}h{minutes:02d}m"
    if minutes:
        return f"{minutes}m{secs:02d}s"
    return f"{secs}s"


class Progress:
    """Counts finished items out of ``total`` and formats one progress line per item.

    Args:
        total: number of items (≥ 0).
        clock: monotonic time in seconds (a stand-in clock in tests).
    """

    def __init__(self, total: int, clock: Callable[[], float] = time.monotonic):
        check_int("total", total, 0)
        self.total = total
        self.finished = 0
        self._clock = clock
        self._start_s = clock()

    def elapsed_s(self) -> float:
        """Seconds since the ``Progress`` was made."""
        return self._clock() - self._start_s

    def eta_s(self) -> float | None:
        """Seconds until the last item finishes at the pace so far (``None`` before the first)."""
        if self.finished == 0:
            return None
        return self.elapsed_s() / self.finished * (self.total - self.finished)

    def line(self, text: str) -> str:
        """Count one finished item; ``"[finished/total] text (elapsed E, ETA R)"`` (no ETA after the last)."""
        self.finished += 1
        timing = f"elapsed {format_duration(self.elapsed_s())}"
        if self.finished < self.total:
            timing += f", ETA {format_duration(self.eta_s())}"
        return f"[{self.finished}/{self.total}] {text} ({timing})"
