"""``attentive_gym.attention`` imports neither gymnasium nor pymunk, and stays light with them installed."""

import subprocess
import sys
import textwrap
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def test_attention_library_works_without_gymnasium_and_pymunk():
    code = textwrap.dedent(
        """
        import sys
        sys.modules["gymnasium"] = None  # importing them now raises ImportError
        sys.modules["pymunk"] = None
        import numpy as np
        import attentive_gym.attention as att
        model = att.AttentionModel()
        model.set_goals(att.Goal.direction_is("towards"))
        for k in range(3):
            out = model.step(0.05 * k, np.full(16, 3.0), np.full(180, 8.0), (0.2, 0.0))
        assert out.F.shape == (6, 8)
        bad = [m for m in ("gymnasium", "pymunk", "matplotlib") if sys.modules.get(m) is not None]
        assert not bad, bad
        print("ok")
        """
    )
    result = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "ok"


def test_importing_the_model_with_gymnasium_installed_loads_no_simulator_renderer_or_torch():
    """Registration (run by ``import attentive_gym``) uses string entry points only."""
    code = textwrap.dedent(
        """
        import sys
        import attentive_gym.attention
        import gymnasium as gym
        for env_id in ("AttentiveRescueFocus-v1", "AttentiveRescueFocus-v0", "AttentiveRescueOracle-v0"):
            assert env_id in gym.registry, env_id
        heavy = [m for m in ("pymunk", "pygame", "torch", "stable_baselines3", "matplotlib",
                             "attentive_gym.envs", "attentive_gym.wrappers") if m in sys.modules]
        assert not heavy, heavy
        print("ok")
        """
    )
    result = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "ok"
