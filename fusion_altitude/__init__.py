"""fusion-altitude: altitude and vertical-velocity estimation for things that fly.

Fuses barometric altitude (m) with gravity-compensated vertical acceleration
(m/s², earth frame, +up) into drift-free altitude, vertical velocity and the
accelerometer's vertical bias. The estimators are C99 (``csrc/``), called
through Cython; :mod:`fusion_altitude.reference` holds readable pure-Python
twins that agree with them bit for bit.

Vertical is +up everywhere; NED users negate.
"""

from ._common import GRAVITY
from ._observer import AltitudeEstimator, AltitudeSettings
from ._observer_glue import AltitudeBatch, DiscretisationWarning, Status
from ._kalman import KalmanEstimator, KalmanSettings
from ._kalman_glue import KalmanBatch, KalmanResult, KalmanSensors, KalmanStatus
from ._complementary import ComplementaryFilter, ComplementarySettings
from ._complementary_glue import ComplementaryBatch, ComplementaryStatus
from ._alphabeta import AlphaBetaFusion, AlphaBetaSettings
from ._alphabeta_glue import AlphaBetaBatch, AlphaBetaSensors, AlphaBetaSensorSettings, AlphaBetaStatus
from ._ins import InsEstimator, InsSettings
from ._ins_glue import InsBatch, InsStatus
from .ins_run import ins_run
from ._version import __version__
from .sensors import altitude_to_pressure, pressure_to_altitude, vertical_acceleration
from .tuning import FitResult, SweepResult, fit, sweep

__all__ = [
    "GRAVITY",
    "AltitudeBatch",
    "AltitudeEstimator",
    "AltitudeSettings",
    "AlphaBetaBatch",
    "AlphaBetaFusion",
    "AlphaBetaSensorSettings",
    "AlphaBetaSensors",
    "AlphaBetaSettings",
    "AlphaBetaStatus",
    "ComplementaryBatch",
    "ComplementaryFilter",
    "ComplementarySettings",
    "ComplementaryStatus",
    "DiscretisationWarning",
    "InsBatch",
    "InsEstimator",
    "InsSettings",
    "InsStatus",
    "FitResult",
    "KalmanBatch",
    "KalmanEstimator",
    "KalmanResult",
    "KalmanSensors",
    "KalmanSettings",
    "KalmanStatus",
    "Status",
    "SweepResult",
    "fit",
    "ins_run",
    "sweep",
    "__version__",
    "altitude_to_pressure",
    "pressure_to_altitude",
    "vertical_acceleration",
]
