"""``--conf-file attentive_gym.agents.rl_zoo.ppo_lstm``: rl-zoo3 reads ``hyperparams`` (``ppo_lstm.yml``)."""

from attentive_gym.agents.rl_zoo import load_hyperparams

hyperparams = load_hyperparams("ppo_lstm")
