"""A Gymnasium environment: closed-loop swimming control in the coupled fluid (the ``gym`` extra).

    import gymnasium as gym
    import aquagait.envs                      # registers aquagait/Swim-v0

    env = gym.make("aquagait/Swim-v0", creature="eel2d", task="forward", seconds=4.0)
    # or, without the import: gym.make("aquagait.envs:aquagait/Swim-v0", ...)

``SwimEnv`` (``aquagait.envs.swim``) documents the observations, actions,
rewards and tasks; ``aquagait.envs.tasks`` the tasks, ``aquagait.envs.sensing``
the lateral line.

Many environments at once, on processes (each builds its own scene; the
first step of each compiles nothing new: Numba's cache is on disk)::

    envs = gym.make_vec("aquagait/Swim-v0", num_envs=2, vectorization_mode="async",
                        creature="eel2d", seconds=4.0)

On a Dask cluster, run whole episodes as tasks: a function that builds the
environment on the worker, plays an episode with the policy's parameters and
returns its return, submitted with ``client.map``. Each worker needs aquagait
with the ``gym`` extra, and a user's MJCF at the same path.
``examples/07_learn_to_swim.py`` trains a controller for eel2d with two
environments on two processes.

Beside ``aquagait.app`` in the layers (docs/development.md): a user's loop drives
``step``; this package imports the simulation, the creatures and the
pictures (for ``render``), and nothing imports it.
"""

import gymnasium

from aquagait.envs.swim import SwimEnv
from aquagait.envs.tasks import TASKS

ENV_ID = "aquagait/Swim-v0"
"""The id ``gymnasium.make`` knows ``SwimEnv`` by, registered on import."""

if ENV_ID not in gymnasium.registry:
    gymnasium.register(id=ENV_ID, entry_point="aquagait.envs.swim:SwimEnv")

__all__ = ["ENV_ID", "TASKS", "SwimEnv"]
