"""Pure-Python reference of the fusion-altitude estimators.

Written to be read next to ``csrc/fusion_altitude.h``: the same public API as
:mod:`fusion_altitude`, float32 arithmetic through numpy scalars in the same
operation order as the C, so its outputs match the C core bit for bit. It is
slow (a Python loop); use it to understand, test and port the algorithm.
"""

from .._core._common import GRAVITY
from .._core._kalman_glue import KalmanResult, KalmanSensors
from .._core._observer_glue import DiscretisationWarning
from .._core._alphabeta_glue import AlphaBetaSensors, AlphaBetaSensorSettings
from .sweep import sweep

# Each estimator's classes: its estimator, settings, batch result and status enum.
# generated: estimator imports -- written by tools/generate_bindings.py from its MODULES; do not edit
from .._core._c_tables import AlphaBetaStatus, ComplementaryStatus, InsStatus, KalmanStatus, RocketStatus, Status
from .._core._observer_glue import AltitudeBatch
from .._core._kalman_glue import KalmanBatch
from .._core._complementary_glue import ComplementaryBatch
from .._core._alphabeta_glue import AlphaBetaBatch
from .._core._ins_glue import InsBatch
from .._core._rocket_glue import RocketBatch
from .observer import AltitudeEstimator, AltitudeSettings
from .kalman import KalmanEstimator, KalmanSettings
from .complementary import ComplementaryFilter, ComplementarySettings
from .alphabeta import AlphaBetaFusion, AlphaBetaSettings
from .ins import InsEstimator, InsSettings
from .rocket import RocketEstimator, RocketSettings
# end generated: estimator imports

__all__ = ["AlphaBetaSensorSettings", "AlphaBetaSensors", "DiscretisationWarning", "GRAVITY", "KalmanResult",
           "KalmanSensors", "sweep"]
# generated: estimator names -- written by tools/generate_bindings.py from its MODULES; do not edit
__all__ += [
    "AltitudeEstimator", "AltitudeSettings", "AltitudeBatch", "Status",
    "KalmanEstimator", "KalmanSettings", "KalmanBatch", "KalmanStatus",
    "ComplementaryFilter", "ComplementarySettings", "ComplementaryBatch", "ComplementaryStatus",
    "AlphaBetaFusion", "AlphaBetaSettings", "AlphaBetaBatch", "AlphaBetaStatus",
    "InsEstimator", "InsSettings", "InsBatch", "InsStatus",
    "RocketEstimator", "RocketSettings", "RocketBatch", "RocketStatus",
]
# end generated: estimator names
