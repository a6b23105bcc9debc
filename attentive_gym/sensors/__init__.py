"""Analytic sensing of a 2-D pymunk scene: exact ray casts and sonar cones, with owner ids.

- ``geometry``: ``SceneGeometry`` (world-frame segments and circles) and
  ``GeometryCache`` (pymunk shapes → exact primitives, re-placed cheaply each step).
- ``raycast``: numba kernels ``cast_rays``, ``cast_fan``, ``cone_nearest``.
- ``sonar``, ``laser``: the P2AT sonar ring and the 180-beam laser, noise-free.
- ``noise``: multiplicative Gaussian range noise.
- ``suite``: ``SensorSuite``, both sensors with noise, returning a ``SensorReading``.

Conventions: world frame in metres and radians; robot frame x forward, y left,
bearings counter-clockwise; owner -1 means "no echo".
"""

from attentive_gym.sensors.geometry import GeometryCache, SceneGeometry, shape_primitives
from attentive_gym.sensors.laser import LaserConfig, LaserScanner
from attentive_gym.sensors.noise import apply_range_noise
from attentive_gym.sensors.raycast import cast_fan, cast_rays, cone_nearest, cone_nearest_points
from attentive_gym.sensors.sonar import P2AT_SONAR_MOUNTS, SonarConfig, SonarRing
from attentive_gym.sensors.suite import SensorReading, SensorSuite

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
    "apply_range_noise",
    "SensorReading",
    "SensorSuite",
]
