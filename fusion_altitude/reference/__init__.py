"""Pure-Python reference of the fusion-altitude estimators.

Written to be read next to ``csrc/fusion_altitude.h``: the same public API as
:mod:`fusion_altitude`, float32 arithmetic through numpy scalars in the same
operation order as the C, so its outputs match the C core bit for bit. It is
slow (a Python loop); use it to understand, test and port the algorithm.
"""

from .._core._common import GRAVITY
from .._core._kalman_glue import KalmanBatch, KalmanResult, KalmanSensors, KalmanStatus
from .._core._observer_glue import AltitudeBatch, DiscretisationWarning, Status
from .._core._alphabeta_glue import AlphaBetaBatch, AlphaBetaSensors, AlphaBetaSensorSettings, AlphaBetaStatus
from .._core._complementary_glue import ComplementaryBatch, ComplementaryStatus
from .._core._rocket_glue import RocketBatch, RocketStatus
from .._core._ins_glue import InsBatch, InsStatus
from .alphabeta import AlphaBetaFusion, AlphaBetaSettings
from .complementary import ComplementaryFilter, ComplementarySettings
from .rocket import RocketEstimator, RocketSettings
from .ins import InsEstimator, InsSettings
from .kalman import KalmanEstimator, KalmanSettings
from .observer import AltitudeEstimator, AltitudeSettings
from .sweep import sweep

__all__ = ["AlphaBetaBatch", "AlphaBetaFusion", "AlphaBetaSensorSettings", "AlphaBetaSensors", "AlphaBetaSettings",
           "AlphaBetaStatus", "ComplementaryBatch", "ComplementaryFilter", "ComplementarySettings", "ComplementaryStatus",
           "GRAVITY", "AltitudeBatch", "AltitudeEstimator", "AltitudeSettings", "DiscretisationWarning", "InsBatch",
           "InsEstimator", "InsSettings", "InsStatus", "KalmanBatch", "KalmanEstimator", "KalmanResult", "KalmanSensors",
           "KalmanSettings", "KalmanStatus", "RocketBatch", "RocketEstimator", "RocketSettings", "RocketStatus",
           "Status", "sweep"]
