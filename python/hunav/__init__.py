"""HuNav-LCM in Python: the simulation in process (``hunav.Simulation``), many worlds stepped together
over threads (``hunav.VectorSimulation``) and Gymnasium-style environments (``hunav.gym.HuNavEnv``,
``hunav.gym.HuNavVectorEnv``). See python/README.md."""
from ._hunav import ConfigError, Simulation, VectorSimulation, planners

__all__ = ["ConfigError", "Simulation", "VectorSimulation", "planners"]
