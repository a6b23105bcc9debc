"""Analytic sensing of a 2-D pymunk scene: exact ray casts and sonar cones, with owner ids.

- ``geometry``: ``SceneGeometry`` (world-frame segments and circles) and
  ``GeometryCache`` (pymunk shapes → exact primitives, re-placed cheaply each step).
- ``raycast``: numba kernels ``cast_rays``, ``cast_fan``, ``cone_nearest``.
- ``sonar``, ``laser``: the P2AT sonar ring and the 180-beam laser, noise-free.
- ``noise``: multiplicative range noise, Gaussian or uniform (``NOISE_MODELS``).
- ``suite``: ``SensorSuite``, both sensors with noise, returning a ``SensorReading``; its
  ``read_batch`` reads N robots in one compiled call into a ``BatchReading``.
- ``stack``: ``SceneStack``, the scenes of N robots packed for ``read_batch``.
- ``scans``: ``ScanHold``, each sensor's reading held between scans at its scan interval.
- ``profiles``: ``SensorProfile`` (noise model, level, scan intervals) and the named
  ``SENSOR_PROFILES`` (``"usarsim"``), resolved by ``resolve_sensor_profile``.

Conventions: world frame in metres and radians; robot frame x forward, y left,
bearings counter-clockwise; owner -1 means "no echo".
"""

from attentive_gym.sensors.geometry import GeometryCache, SceneGeometry, shape_primitives
from attentive_gym.sensors.laser import LaserConfig, LaserScanner
from attentive_gym.sensors.noise import (
    NOISE_MODELS,
    apply_range_noise,
    check_noise_model,
    unit_noise,
    unit_noise_rows,
)
from attentive_gym.sensors.profiles import (
    DEFAULT_SENSOR_PROFILE,
    SENSOR_PROFILES,
    USARSIM_SCAN_INTERVAL_S,
    SensorProfile,
    resolve_sensor_profile,
)
from attentive_gym.sensors.raycast import cast_fan, cast_rays, cone_nearest, cone_nearest_points
from attentive_gym.sensors.scans import SCAN_TOLERANCE_S, ScanHold, scan_due
from attentive_gym.sensors.sonar import P2AT_SONAR_MOUNTS, SonarConfig, SonarRing
from attentive_gym.sensors.stack import SceneStack
from attentive_gym.sensors.suite import BatchReading, SensorReading, SensorSuite

__all__ = [
    "SceneGeometry",
    "GeometryCache",
    "shape_primitives",
    "cast_rays",
    "cast_fan",
    "cone_nearest",
    "cone_nearest_points",
    "P2AT_SONAR_MOUNTS",
    "SonarConfig",
    "SonarRing",
    "LaserConfig",
    "LaserScanner",
    "NOISE_MODELS",
    "apply_range_noise",
    "check_noise_model",
    "unit_noise",
    "unit_noise_rows",
    "SensorReading",
    "SensorSuite",
    "BatchReading",
    "SceneStack",
    "SCAN_TOLERANCE_S",
    "ScanHold",
    "scan_due",
    "SensorProfile",
    "DEFAULT_SENSOR_PROFILE",
    "SENSOR_PROFILES",
    "USARSIM_SCAN_INTERVAL_S",
    "resolve_sensor_profile",
]
