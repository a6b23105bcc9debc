"""Idempotent registration of the package's environments with Gymnasium.

An id's version changes whenever what it builds changes: the task (``envs.tasks.TASK_VERSIONS``)
or, for the variants that run the attentional model, the model's defaults
(``attention.MODEL_VERSIONS``). ``VARIANT_IDS`` build the current task and model;
``EARLIER_IDS`` the earlier ones, kept so that their results and policies reproduce:

| id version | raw, raw-stack, oracle | the attended variants |
|---|---|---|
| task 0, model 0 | ``-v0`` | ``-v0`` |
| task 0, model 1 | ``-v0`` | ``-v1`` |
| task 1, model 1 | ``-v1`` | ``-v2`` |
| task 1, model 2 | ``-v1`` | ``-v3`` |
| task 1, model 3 (current) | ``-v1`` | ``-v4`` |

Every id is built by ``attentive_gym.wrappers.variants:make_env`` and has a vector entry
point (``gym.make_vec(id, num_envs=N, vectorization_mode="vector_entry_point")``:
``attentive_gym.vector.vector_env``). Entry points are strings, so that registering (which
``import attentive_gym`` does) loads neither the simulator nor the wrappers:
``import attentive_gym.attention`` stays light.
"""

from gymnasium.envs.registration import register, registry

__all__ = ["VARIANT_IDS", "EARLIER_IDS", "ID_VERSIONS", "MODEL_VARIANTS", "register_environments", "registered_id"]

#: The variants whose observation the attentional model makes (the others run no model).
MODEL_VARIANTS = frozenset({"focus", "saliency", "masked", "goal-action", "random-focus"})
_BASES = {
    "raw": "AttentiveRescue",
    "raw-stack": "AttentiveRescueStack",
    "focus": "AttentiveRescueFocus",
    "saliency": "AttentiveRescueSaliency",
    "masked": "AttentiveRescueMasked",
    "goal-action": "AttentiveRescueGoalAction",
    "oracle": "AttentiveRescueOracle",
    "random-focus": "AttentiveRescueRandomFocus",
}


def registered_id(variant: str, task: int, model: int) -> str:
    """The id of ``variant`` on task version ``task`` and model version ``model`` (a pair of
    the table above; the variants that run no model ignore ``model``)."""
    if variant not in MODEL_VARIANTS:
        return f"{_BASES[variant]}-v{task}"
    return f"{_BASES[variant]}-v{task + model}"


#: The ``(task, model)`` versions that have ids, the current one last (the table above).
_VERSIONS = ((0, 0), (0, 1), (1, 1), (1, 2), (1, 3))
#: Variant name → its registered id on the current task and model.
VARIANT_IDS: dict[str, str] = {variant: registered_id(variant, *_VERSIONS[-1]) for variant in _BASES}
#: Every registered id → ``(variant, task version, model version)``; the model version is
#: that of the ``make_env`` call, which the variants that run no model ignore (an id they
#: share between model versions builds the latest of them).
ID_VERSIONS: dict[str, tuple[str, int, int]] = {
    registered_id(variant, task, model): (variant, task, model) for task, model in _VERSIONS for variant in _BASES
}
#: The ids of earlier task or model versions, each → ``(variant, task, model)``.
EARLIER_IDS: dict[str, tuple[str, int, int]] = {
    env_id: versions for env_id, versions in ID_VERSIONS.items() if env_id not in VARIANT_IDS.values()
}

_ENTRY_POINT = "attentive_gym.wrappers.variants:make_env"
_VECTOR_ENTRY_POINT = "attentive_gym.vector.vector_env:make_vector_env"


def register_environments() -> None:
    """Register every environment of the package once; later calls do nothing."""
    for env_id, (variant, task, model) in ID_VERSIONS.items():
        if env_id in registry:
            continue
        register(
            id=env_id,
            entry_point=_ENTRY_POINT,
            vector_entry_point=_VECTOR_ENTRY_POINT,
            kwargs={"variant": variant, "task": task, "version": model},
            max_episode_steps=None,
        )
