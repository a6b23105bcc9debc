"""Shared assertions of the reliability tests."""

import traceback

import numpy as np


def assert_clear_error(error: BaseException, *names: str) -> None:
    """``error`` is a ValueError/TypeError raised by attentive_gym whose message names one of ``names``."""
    assert isinstance(error, (ValueError, TypeError)), f"{type(error).__name__}: {error}"
    message = str(error).lower()
    assert any(name.lower() in message for name in names), f"message {str(error)!r} names none of {names}"
    frames = traceback.extract_tb(error.__traceback__)
    innermost = frames[-1].filename if frames else ""
    assert "attentive_gym" in innermost, f"raised deep inside {innermost}, not by attentive_gym's validation: {error}"


def outcome(call):
    """``(result, None)`` or ``(None, exception)`` of ``call()``."""
    try:
        return call(), None
    except Exception as error:  # noqa: BLE001 - classified by the caller
        return None, error


def assert_finite_observation(env, obs) -> None:
    for key, value in obs.items():
        assert np.all(np.isfinite(value)), f"obs[{key!r}] is not finite"
    assert env.observation_space.contains(obs)
