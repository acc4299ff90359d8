"""The simulators and their scenarios: :mod:`~fusion_altitude.sim.trajectories` (trajectories, IMU, baro,
rangefinder and GPS models, log faults; its names are this package's, as ``fusion_altitude.sim`` was one module),
:mod:`~fusion_altitude.sim.imu_sim` (a raw IMU through an AHRS), :mod:`~fusion_altitude.sim.rocket_sim` (transonic
rocket flights) and :mod:`~fusion_altitude.sim.scenarios` (the published comparison scenarios)."""

from .trajectories import *  # noqa: F401,F403  (the public names of the former module fusion_altitude.sim)
from .trajectories import GRAVITY, __all__  # noqa: F401
