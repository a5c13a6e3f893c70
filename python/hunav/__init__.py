"""HuNav-LCM in Python: the simulation in process (``hunav.Simulation``) and a Gymnasium-style
environment (``hunav.gym.HuNavEnv``). See python/README.md."""
from ._hunav import ConfigError, Simulation, planners

__all__ = ["ConfigError", "Simulation", "planners"]
