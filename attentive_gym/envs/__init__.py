"""Gymnasium environments.

- ``rescue_env``: ``AttentiveRescueEnv``, registered as ``AttentiveRescue-v0``.
- ``reward``: ``RewardConfig`` and the shaped rescue reward.
- ``geodesic``: the path length to the target round walls and rubble, which a geodesic
  progress reward counts.
- ``config_mappings``: the env's settings objects (reward, robot, sonar, laser) from plain
  mappings and back (``--env-kwargs``, ``spec.json``).
- ``rendering``: ``WorldRenderer``, the pygame top-down view.

The batched environments moved to ``attentive_gym.vector``; their old paths
``attentive_gym.envs.fleet`` and ``attentive_gym.envs.vector_env`` still import, with a
``DeprecationWarning``.
"""

from attentive_gym import _moved
from attentive_gym.envs.rescue_env import AttentiveRescueEnv
from attentive_gym.envs.reward import RewardConfig

__all__ = ["AttentiveRescueEnv", "RewardConfig"]

_moved.install(
    {f"{__name__}.fleet": "attentive_gym.vector.fleet", f"{__name__}.vector_env": "attentive_gym.vector.vector_env"}
)


def __getattr__(name: str):
    """An old module path read as an attribute (``attentive_gym.envs.fleet``): the moved module."""
    return _moved.attribute(__name__, name)
