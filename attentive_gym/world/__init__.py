"""The pymunk search-and-rescue world: scenarios, the robot, moving actors, arenas.

- ``scenario``: frozen, validated descriptions of a world (walls, rubble, movers, task).
- ``scenario_io``: load and save scenarios as YAML or JSON, with located errors.
- ``behaviours``: how movers move (scripted paths, pursuit, evasion).
- ``robot``: the Pioneer P2AT-like differential-drive robot.
- ``world``: ``World``, a pymunk space stepped with the robot's velocity commands.
- ``state``: the world's control state as numpy records.
- ``compiled``: ``step_worlds``, the world step for many worlds in one compiled call.
- ``builtin``: the five experiment scenarios of the paper.
- ``arena``: seeded random arenas for training.

Units: metres, seconds, radians, world frame with x east and y north.
"""

from attentive_gym.world.arena import ArenaConfig, generate_arena
from attentive_gym.world.builtin import BUILTIN_SCENARIOS, builtin_scenario
from attentive_gym.world.compiled import step_worlds
from attentive_gym.world.robot import RobotConfig
from attentive_gym.world.scenario import Scenario, TaskSpec
from attentive_gym.world.scenario_io import load_scenario, save_scenario
from attentive_gym.world.world import World

__all__ = [
    "ArenaConfig",
    "BUILTIN_SCENARIOS",
    "RobotConfig",
    "Scenario",
    "TaskSpec",
    "World",
    "builtin_scenario",
    "generate_arena",
    "load_scenario",
    "save_scenario",
    "step_worlds",
]
