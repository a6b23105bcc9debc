"""Gymnasium environments.

- ``rescue_env``: ``AttentiveRescueEnv``, registered as ``AttentiveRescue-v0``.
- ``reward``: ``RewardConfig`` and the shaped rescue reward.
- ``rendering``: ``WorldRenderer``, the pygame top-down view.
"""

from attentive_gym.envs.rescue_env import AttentiveRescueEnv
from attentive_gym.envs.reward import RewardConfig

__all__ = ["AttentiveRescueEnv", "RewardConfig"]
