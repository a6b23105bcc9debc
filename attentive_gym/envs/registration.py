"""Idempotent registration of the package's environments with Gymnasium."""

from gymnasium.envs.registration import register, registry

__all__ = ["ENVIRONMENT_IDS", "register_environments"]

#: id -> (entry point, extra registration keyword arguments)
_SPECS = {
    "AttentiveRescue-v0": ("attentive_gym.envs.rescue_env:AttentiveRescueEnv", {"max_episode_steps": None}),
}
ENVIRONMENT_IDS = tuple(_SPECS)


def register_environments() -> None:
    """Register every environment of the package once; later calls do nothing."""
    for env_id, (entry_point, kwargs) in _SPECS.items():
        if env_id not in registry:
            register(id=env_id, entry_point=entry_point, **kwargs)
