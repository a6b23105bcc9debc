"""Idempotent registration of the package's environments with Gymnasium.

``AttentiveRescue-v0`` is the base environment; the other ids are its observation
variants (``attentive_gym.wrappers.variants``).
"""

from gymnasium.envs.registration import register, registry

__all__ = ["register_environments"]

_BASE_ID = "AttentiveRescue-v0"


def register_environments() -> None:
    """Register every environment of the package once; later calls do nothing."""
    from attentive_gym.wrappers.variants import registered_entry_points

    entry_points = {_BASE_ID: "attentive_gym.envs.rescue_env:AttentiveRescueEnv", **registered_entry_points()}
    for env_id, entry_point in entry_points.items():
        if env_id not in registry:
            register(id=env_id, entry_point=entry_point, max_episode_steps=None)

