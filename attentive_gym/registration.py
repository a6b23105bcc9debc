"""Idempotent registration of the package's environments with Gymnasium.

``AttentiveRescue-v0`` is the base environment; the other ids are its observation
variants (``attentive_gym.wrappers.variants``). Every id has a vector entry point
(``gym.make_vec(id, num_envs=N, vectorization_mode="vector_entry_point")``:
``attentive_gym.vector.vector_env``). Entry points are strings, so that
registering (which ``import attentive_gym`` does) loads neither the simulator nor the
wrappers: ``import attentive_gym.attention`` stays light.
"""

from gymnasium.envs.registration import register, registry

__all__ = ["VARIANT_IDS", "register_environments"]

#: Variant name → registered environment id.
VARIANT_IDS: dict[str, str] = {
    "raw": "AttentiveRescue-v0",
    "raw-stack": "AttentiveRescueStack-v0",
    "focus": "AttentiveRescueFocus-v0",
    "saliency": "AttentiveRescueSaliency-v0",
    "masked": "AttentiveRescueMasked-v0",
    "goal-action": "AttentiveRescueGoalAction-v0",
    "oracle": "AttentiveRescueOracle-v0",
    "random-focus": "AttentiveRescueRandomFocus-v0",
}

_BASE_ENTRY_POINT = "attentive_gym.envs.rescue_env:AttentiveRescueEnv"
_VARIANT_ENTRY_POINT = "attentive_gym.wrappers.variants:make_env"
_VECTOR_ENTRY_POINT = "attentive_gym.vector.vector_env:make_vector_env"


def register_environments() -> None:
    """Register every environment of the package once; later calls do nothing."""
    for variant, env_id in VARIANT_IDS.items():
        if env_id in registry:
            continue
        if variant == "raw":
            register(
                id=env_id, entry_point=_BASE_ENTRY_POINT, vector_entry_point=_VECTOR_ENTRY_POINT, max_episode_steps=None
            )
        else:
            register(
                id=env_id,
                entry_point=_VARIANT_ENTRY_POINT,
                vector_entry_point=_VECTOR_ENTRY_POINT,
                kwargs={"variant": variant},
                max_episode_steps=None,
            )
