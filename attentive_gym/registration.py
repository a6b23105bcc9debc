"""Idempotent registration of the package's environments with Gymnasium.

``AttentiveRescue-v0`` is the base environment; the other ids are its observation
variants (``attentive_gym.wrappers.variants``). The attended variants' ids carry the version
of the model's defaults (``attention.MODEL_VERSIONS``): ``-v1`` the current one, ``-v0`` the
first (``VERSION_0_IDS``), kept so that results and policies of version 0 reproduce. Every id has a vector entry point
(``gym.make_vec(id, num_envs=N, vectorization_mode="vector_entry_point")``:
``attentive_gym.vector.vector_env``). Entry points are strings, so that
registering (which ``import attentive_gym`` does) loads neither the simulator nor the
wrappers: ``import attentive_gym.attention`` stays light.
"""

from gymnasium.envs.registration import register, registry

__all__ = ["VARIANT_IDS", "VERSION_0_IDS", "register_environments"]

#: Variant name → registered environment id (the current version).
VARIANT_IDS: dict[str, str] = {
    "raw": "AttentiveRescue-v0",
    "raw-stack": "AttentiveRescueStack-v0",
    "focus": "AttentiveRescueFocus-v1",
    "saliency": "AttentiveRescueSaliency-v1",
    "masked": "AttentiveRescueMasked-v1",
    "goal-action": "AttentiveRescueGoalAction-v1",
    "oracle": "AttentiveRescueOracle-v0",
    "random-focus": "AttentiveRescueRandomFocus-v1",
}
#: Attended variant → its id with the model's version 0 defaults.
VERSION_0_IDS: dict[str, str] = {
    variant: env_id.replace("-v1", "-v0") for variant, env_id in VARIANT_IDS.items() if env_id.endswith("-v1")
}

_BASE_ENTRY_POINT = "attentive_gym.envs.rescue_env:AttentiveRescueEnv"
_VARIANT_ENTRY_POINT = "attentive_gym.wrappers.variants:make_env"
_VECTOR_ENTRY_POINT = "attentive_gym.vector.vector_env:make_vector_env"


def register_environments() -> None:
    """Register every environment of the package once; later calls do nothing."""
    ids = [(variant, env_id, {}) for variant, env_id in VARIANT_IDS.items()]
    ids += [(variant, env_id, {"version": 0}) for variant, env_id in VERSION_0_IDS.items()]
    for variant, env_id, version in ids:
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
                kwargs={"variant": variant, **version},
                max_episode_steps=None,
            )
