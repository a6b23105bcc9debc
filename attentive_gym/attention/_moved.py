"""The old module paths of the attention library, kept importable with a ``DeprecationWarning``.

The library's modules were flat under ``attentive_gym.attention`` before they were grouped
into ``tracking``, ``compiled`` and ``io``. ``install`` registers their old paths with the
package's finder of moved modules (``attentive_gym._moved``), which answers an old path
(``import attentive_gym.attention.tracker``, ``from attentive_gym.attention import tracker``,
unpickling an object saved under an old path) with the module at its new path, the same
module object, after warning that it moved. The new paths never warn.
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

from attentive_gym import _moved

__all__ = ["MOVED", "install"]

_PACKAGE = "attentive_gym.attention"
#: Old module path → the module's path now.
MOVED: Mapping[str, str] = MappingProxyType(
    {
        f"{_PACKAGE}.{old}": f"{_PACKAGE}.{new}"
        for old, new in (
            ("tracker", "tracking.tracker"),
            ("kalman", "tracking.kalman"),
            ("association", "tracking.association"),
            ("segmentation", "tracking.segmentation"),
            ("track_regions", "tracking.track_regions"),
            ("step_kernels", "compiled.step_kernels"),
            ("batch", "compiled.batch"),
            ("replay", "io.replay"),
            ("rosbag", "io.rosbag"),
            ("ros_readings", "io.ros_readings"),
            ("trace", "io.trace"),
        )
    }
)


def install() -> None:
    """Register the old paths with the finder of moved modules (once, however often it is called)."""
    _moved.install(MOVED)
