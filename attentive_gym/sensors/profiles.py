"""Sensor profiles: named noise models, noise levels and scan rates for the robot's sensors.

- ``SensorProfile``: the noise model, its level and each sensor's scan interval (frozen).
- ``DEFAULT_SENSOR_PROFILE``: the settings without a profile (5 % Gaussian, a scan every step).
- ``SENSOR_PROFILES``: the named profiles; ``"usarsim"`` is USARSim's defaults
  (``Noise`` 0.05 applied as ``(1 + RandRange(-Noise, Noise)) * reading``, ``ScanInterval`` 0.2 s).
- ``resolve_sensor_profile``: a profile name plus explicit settings → the settings in force.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from types import MappingProxyType

from attentive_gym.sensors._checks import check_relative_std, check_scan_interval
from attentive_gym.sensors.noise import check_noise_model

__all__ = [
    "DEFAULT_SENSOR_PROFILE",
    "SENSOR_PROFILES",
    "USARSIM_SCAN_INTERVAL_S",
    "SensorProfile",
    "resolve_sensor_profile",
]


@dataclass(frozen=True)
class SensorProfile:
    """How the sonar ring and the laser are simulated: noise and scan rates.

    Attributes:
        noise_model: one of ``noise.NOISE_MODELS`` (``"gaussian"`` or ``"uniform"``).
        noise: the relative noise level, finite, in [0, 1): sigma for ``"gaussian"``, the
            half-width ``a`` of ``U[-a, a)`` for ``"uniform"``.
        sonar_scan_interval_s: seconds between sonar scans (> 0, finite), or ``None`` for a
            scan every env step; between scans the last reading holds.
        laser_scan_interval_s: the same for the laser.

    Raises:
        ValueError: for a bad field, naming it and what is allowed.
    """

    noise_model: str
    noise: float
    sonar_scan_interval_s: float | None
    laser_scan_interval_s: float | None

    def __post_init__(self) -> None:
        set_field = object.__setattr__  # the checked, converted values, on a frozen instance
        set_field(self, "noise_model", check_noise_model("noise_model", self.noise_model))
        set_field(self, "noise", check_relative_std("noise", self.noise))
        for name in ("sonar_scan_interval_s", "laser_scan_interval_s"):
            set_field(self, name, check_scan_interval(name, getattr(self, name)))


#: The settings when no profile is named: 5 % Gaussian noise, both sensors scanned every step.
DEFAULT_SENSOR_PROFILE = SensorProfile("gaussian", 0.05, None, None)

#: USARSim's default ``ScanInterval`` of the sonar and the range scanner (s): 5 Hz.
USARSIM_SCAN_INTERVAL_S = 0.2

#: The named profiles (read-only). ``"usarsim"``: ±5 % uniform noise, both sensors at 5 Hz.
SENSOR_PROFILES = MappingProxyType(
    {
        "usarsim": SensorProfile("uniform", 0.05, USARSIM_SCAN_INTERVAL_S, USARSIM_SCAN_INTERVAL_S),
    }
)


def resolve_sensor_profile(
    profile: str | None,
    *,
    noise_model: str | None = None,
    noise: float | None = None,
    sonar_scan_interval_s: float | None = None,
    laser_scan_interval_s: float | None = None,
) -> SensorProfile:
    """The settings in force: profile ``profile`` with every given setting replacing its own.

    ``None`` means "not given" for every argument: ``profile=None`` starts from
    ``DEFAULT_SENSOR_PROFILE``, and a ``None`` setting keeps the profile's value (so a
    profile's scan interval cannot be turned back into "every step" with ``None``; pass the
    env's ``dt`` instead).

    Args:
        profile: a key of ``SENSOR_PROFILES``, or ``None``.
        noise_model, noise, sonar_scan_interval_s, laser_scan_interval_s: as in ``SensorProfile``.

    Returns:
        The resolved, checked ``SensorProfile``.

    Raises:
        ValueError: for an unknown profile (listing the allowed ones) or a bad setting.

    Example:
        >>> resolve_sensor_profile("usarsim", laser_scan_interval_s=0.1)
        SensorProfile(noise_model='uniform', noise=0.05, sonar_scan_interval_s=0.2, laser_scan_interval_s=0.1)
    """
    if profile is None:
        base = DEFAULT_SENSOR_PROFILE
    elif isinstance(profile, str) and profile in SENSOR_PROFILES:
        base = SENSOR_PROFILES[profile]
    else:
        raise ValueError(f"unknown sensor_profile {profile!r}; allowed: None or one of {sorted(SENSOR_PROFILES)}")
    given = {
        "noise_model": noise_model,
        "noise": noise,
        "sonar_scan_interval_s": sonar_scan_interval_s,
        "laser_scan_interval_s": laser_scan_interval_s,
    }
    return dataclasses.replace(base, **{name: value for name, value in given.items() if value is not None})
