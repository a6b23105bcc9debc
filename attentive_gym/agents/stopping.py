"""Stopping on Ctrl-C and SIGTERM: the ``Interrupted`` exception and the signal handling around it.

Inside ``raise_on_stop_signals()`` SIGINT and SIGTERM raise ``Interrupted`` and are recorded.
A signal handler runs between any two bytecodes, also inside a finalizer or a C library's
callback (pymunk frees its spaces in one), where Python drops the exception; long loops
(``backends``' wait loops, ``training``'s callback at every env step) therefore call
``raise_if_stopped``, which raises the recorded signal's ``Interrupted`` again. A compiled
callee (numba) wraps the handler's exception in a ``SystemError``; any exception that
leaves the block after a stop signal arrived leaves it as that signal's ``Interrupted``.

``signals_blocked`` holds signals back from a thread (and from the processes it starts),
so that a child never sees a Ctrl-C meant for its parent.

This module imports nothing from the rest of ``attentive_gym.agents``: ``backends`` (which
runs ``training``) and ``training`` both build on it.
"""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
from collections.abc import Callable, Iterable, Iterator
from typing import Any

__all__ = [
    "STOP_SIGNALS",
    "Interrupted",
    "raise_if_stopped",
    "raise_if_stopped_from",
    "raise_on_stop_signals",
    "signals_blocked",
    "stop_on_sigterm_only",
    "stop_signals_ignored",
    "quiet_teardown",
]

#: Signals that stop ``run_many`` (and ``attentive-gym train``).
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)
#: Stop signals received in this process (inside ``raise_on_stop_signals``, or in a run process), oldest first.
_received: list[int] = []


class Interrupted(KeyboardInterrupt):
    """A stop signal arrived. ``signum``: which one; ``exit_status``: the shell's ``128 + signum``.

    ``str()`` is one line: ``"interrupted by SIGINT"`` plus ``detail`` (what finished, how to resume).
    """

    def __init__(self, signum: int, detail: str = ""):
        self.signum = int(signum)
        self.detail = detail
        message = f"interrupted by {signal.Signals(self.signum).name}"
        super().__init__(f"{message}; {detail}" if detail else message)

    @property
    def exit_status(self) -> int:
        return 128 + self.signum


def _raise_interrupted(signum: int, _frame: Any) -> None:
    """The stop signals' handler: record ``signum``, raise its ``Interrupted``."""
    _received.append(signum)
    raise Interrupted(signum)


def raise_if_stopped_from(err: Exception) -> None:
    """Raise the received stop signal's ``Interrupted`` from ``err`` if a stop signal arrived:
    ``err`` is then the handler's exception as a compiled callee wrapped it (numba raises
    ``SystemError`` "returned a result with an exception set")."""
    if _received:
        raise Interrupted(_received[0]) from err


def raise_if_stopped() -> None:
    """Raise ``Interrupted`` if a stop signal was received, in case its own exception got lost
    (see the module docstring)."""
    if _received:
        raise Interrupted(_received[0])


def _quiet_about_lost_interrupts(passed_on: Callable[[Any], None]) -> Callable[[Any], None]:
    """A ``sys.unraisablehook`` silent about an ``Interrupted`` that a finalizer dropped (``raise_if_stopped``
    raises it again) and, once a stop signal has arrived, about any finalizer's error (see
    ``quiet_teardown``), passing anything else on to ``passed_on``."""

    def hook(unraisable: Any) -> None:
        if not isinstance(unraisable.exc_value, Interrupted) and not _received:
            passed_on(unraisable)

    return hook


def quiet_teardown() -> None:
    """Report no finalizer's error from here on: call once a stop signal has ended the work. The
    interpreter's teardown then finalizes objects the stop cut short (a numba compilation's
    LLVM objects among them, whose ``__del__`` can fail), and their errors are the stop's
    consequences, not faults to show the user as an "Exception ignored ... Traceback"."""
    sys.unraisablehook = lambda unraisable: None


@contextlib.contextmanager
def _lost_interrupts_quiet() -> Iterator[None]:
    """Inside the block a dropped ``Interrupted`` is not reported (no "Exception ignored ... Traceback")."""
    previous = sys.unraisablehook
    sys.unraisablehook = _quiet_about_lost_interrupts(previous)
    try:
        yield
    finally:
        sys.unraisablehook = previous


@contextlib.contextmanager
def _stop_signal_handler(handler: Any) -> Iterator[None]:
    """``handler`` for SIGINT and SIGTERM inside the block (main thread only; elsewhere a no-op)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {signum: signal.signal(signum, handler) for signum in STOP_SIGNALS}
    try:
        yield
    finally:
        for signum, old in previous.items():
            signal.signal(signum, old)


@contextlib.contextmanager
def raise_on_stop_signals() -> Iterator[None]:
    """Inside the block SIGINT and SIGTERM raise ``Interrupted`` (main thread only) and are recorded for
    ``raise_if_stopped``; the record is cleared on entry and exit.

    Any ``Exception`` that leaves the block after a stop signal arrived leaves it as that
    signal's ``Interrupted`` (``raise_if_stopped_from``).
    """
    _received.clear()
    try:
        with _stop_signal_handler(_raise_interrupted), _lost_interrupts_quiet():
            try:
                yield
            except Exception as err:
                raise_if_stopped_from(err)
                raise
    finally:
        _received.clear()


def stop_signals_ignored() -> contextlib.AbstractContextManager[None]:
    """SIGINT and SIGTERM ignored inside the block (main thread only), so that stopping is not cut short."""
    return _stop_signal_handler(signal.SIG_IGN)


def stop_on_sigterm_only() -> None:
    """Set up a child process that its parent stops: SIGINT ignored (Ctrl-C reaches the whole
    process group; the parent decides), SIGTERM raises ``Interrupted`` with no report of a
    dropped one nor of a finalizer's error after it, and both stop signals unblocked (a parent
    inside ``signals_blocked`` starts its children with them blocked). Main thread only."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, _raise_interrupted)
    sys.unraisablehook = _quiet_about_lost_interrupts(sys.unraisablehook)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, STOP_SIGNALS)


@contextlib.contextmanager
def signals_blocked(signals: Iterable[int] = STOP_SIGNALS) -> Iterator[None]:
    """Block ``signals`` in this thread inside the block; one that arrives is delivered at its end.

    Processes started inside the block inherit the blocked mask, so they never see those
    signals unless they unblock them (SB3's ``SubprocVecEnv`` workers do not).
    """
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, signals)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)
