"""attentive_gym: a bio-inspired multi-sensor attentional model for robots.

Layers, from the bottom up:

- ``attentive_gym.attention``: the attentional model, pure numpy (no gymnasium, no pymunk).
- ``attentive_gym.sensors``: analytic sonar-ring and laser-scanner simulation.
- ``attentive_gym.world``: the pymunk search-and-rescue world and its scenarios.
- ``attentive_gym.envs``: the Gymnasium environments (``AttentiveRescue-v0``).
- ``attentive_gym.wrappers``: the observation variants (attention, stacks, the oracle).
- ``attentive_gym.vector``: many environments stepped as one (Gymnasium's and SB3's vector envs).
- ``attentive_gym.perception``, ``attentive_gym.viz``; ``attentive_gym.agents``,
  ``attentive_gym.experiments``; the command line (``attentive_gym.cli``).

A module imports only its own subpackage and the layers below it (``tests/test_layers.py``).

Importing the package registers the environments with Gymnasium (idempotently, by
string entry points: ``attentive_gym.registration``), so
``gym.make("attentive_gym:AttentiveRescue-v0")`` works in spawned subprocesses too, and
``import attentive_gym.attention`` loads neither pymunk, pygame nor torch.
"""

from importlib import metadata as _metadata
from pathlib import Path as _Path

from attentive_gym._kernel_cache import discard_stale_kernels as _discard_stale_kernels

_discard_stale_kernels(_Path(__file__).parent)  # before any compiled kernel loads from the cache

try:  # the attention library must stay usable without gymnasium installed
    import gymnasium as _gymnasium
except ImportError:  # pragma: no cover - exercised by tests/attention/test_standalone.py
    _gymnasium = None

if _gymnasium is not None:
    from attentive_gym.registration import register_environments

    register_environments()

try:  # the version lives in pyproject.toml only
    __version__ = _metadata.version("attentive_gym")
except _metadata.PackageNotFoundError:  # a source tree on sys.path, not installed
    __version__ = "0+unknown"
