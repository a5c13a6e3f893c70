"""HuNav-LCM in Python.

- The LCM message classes of every HuNav-LCM channel (``hunav.robot_observation_t``,
  ``hunav.robot_command_t``, ``hunav.map_t``, ...: generated from lcmtypes/ by lcm-gen), for a
  planner process that speaks LCM (with ``import lcm``; docs/planner_contract.md). They need neither
  numpy nor the simulation.
- The simulation in process (``hunav.Simulation``), many worlds stepped together over threads
  (``hunav.VectorSimulation``) and Gymnasium-style environments (``hunav.gym.HuNavEnv``,
  ``hunav.gym.HuNavVectorEnv``), loaded on first use. See python/README.md.
"""
from . import _messages
from ._messages import *  # noqa: F401,F403 (the message classes)

MESSAGES = tuple(sorted(name for name in vars(_messages) if name.endswith("_t")))
_SIMULATION = ("ConfigError", "Simulation", "VectorSimulation", "planners")

__all__ = list(_SIMULATION) + list(MESSAGES)


def __getattr__(name):
    # The simulation's native extension (and numpy) load only when the simulation is used.
    if name in _SIMULATION:
        from . import _hunav

        value = getattr(_hunav, name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'hunav' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_SIMULATION))
