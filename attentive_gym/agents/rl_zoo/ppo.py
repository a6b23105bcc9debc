"""``--conf-file attentive_gym.agents.rl_zoo.ppo``: rl-zoo3 reads ``hyperparams`` (``ppo.yml``)."""

from attentive_gym.agents.rl_zoo import load_hyperparams

hyperparams = load_hyperparams("ppo")
