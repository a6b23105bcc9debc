"""Figures (matplotlib, imported lazily inside each module's functions).

- ``trace_figure.plot_trace``: a recorded attention trace in the paper's layout.
"""

from attentive_gym.viz.trace_figure import plot_trace

__all__ = ["plot_trace"]
