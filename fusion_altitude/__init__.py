"""fusion-altitude: altitude and vertical-velocity estimation for things that fly.

Fuses barometric altitude (m) with gravity-compensated vertical acceleration
(m/s², earth frame, +up) into drift-free altitude, vertical velocity and the
accelerometer's vertical bias. The estimators are C99 (``csrc/``), called
through Cython; :mod:`fusion_altitude.reference` holds readable pure-Python
twins that agree with them bit for bit, and works without the compiled
extension.

Vertical is +up everywhere; NED users negate.

Layers (see docs/architecture.md, checked by import-linter): the C core (``csrc/``); ``_core/`` (the thin
bindings ``_<estimator>.pyx``, their generated files and the glue); ``reference/``; the shared helpers
(``sensors``, ``metrics``, ``health``, ``outputs``); ``tuning``; ``logs/``; ``sim/``; the applications
(``estimators``, the registry; ``adapters``; ``runner``; ``comparison``; ``fleet``; ``rocket``; ``plotting``);
``cli/``.
"""

from . import _aliases

_aliases.install()

from ._core._c_tables import KalmanResult
from ._core._common import GRAVITY
from ._version import __version__
from ._core._observer_glue import DiscretisationWarning
from ._core._kalman_glue import KalmanSensors
from ._core._alphabeta_glue import AlphaBetaSensors, AlphaBetaSensorSettings
from .sensors import altitude_to_pressure, pressure_to_altitude, vertical_acceleration

#: The public names that need the compiled extension (the estimator classes are added below).
_COMPILED = ("ins_run", "FitResult", "SweepResult", "fit", "sweep")

# Each estimator's classes: its estimator, settings, batch result and status enum.
# generated: estimator imports -- written by tools/generate_bindings.py from its MODULES; do not edit
from ._core._c_tables import AlphaBetaStatus, ComplementaryStatus, InsStatus, KalmanStatus, RocketStatus, Status
from ._core._observer_glue import AltitudeBatch
from ._core._kalman_glue import KalmanBatch
from ._core._complementary_glue import ComplementaryBatch
from ._core._alphabeta_glue import AlphaBetaBatch
from ._core._ins_glue import InsBatch
from ._core._rocket_glue import RocketBatch
from .reference.observer import AltitudeSettings
from .reference.kalman import KalmanSettings
from .reference.complementary import ComplementarySettings
from .reference.alphabeta import AlphaBetaSettings
from .reference.ins import InsSettings
from .reference.rocket import RocketSettings
_COMPILED += (
    "AltitudeEstimator", "KalmanEstimator", "ComplementaryFilter", "AlphaBetaFusion", "InsEstimator", "RocketEstimator",
)
# end generated: estimator imports


try:
    # generated: compiled estimators -- written by tools/generate_bindings.py from its MODULES; do not edit
    from ._core._observer import AltitudeEstimator
    from ._core._kalman import KalmanEstimator
    from ._core._complementary import ComplementaryFilter
    from ._core._alphabeta import AlphaBetaFusion
    from ._core._ins import InsEstimator
    from ._core._rocket import RocketEstimator
    # end generated: compiled estimators
    from .ins_run import ins_run
    from .tuning import FitResult, SweepResult, fit, sweep
except ImportError as _error:  # not built: fusion_altitude.reference and the tables still import
    _IMPORT_ERROR = _error

    def __getattr__(name: str):
        if name in _COMPILED:
            raise ImportError(f"fusion_altitude.{name} needs the compiled extension, which failed to import "
                              f"({_IMPORT_ERROR}); build it with `pip install .`, or use fusion_altitude.reference"
                              ) from _IMPORT_ERROR
        raise AttributeError(f"module 'fusion_altitude' has no attribute {name!r}")

__all__ = [
    "GRAVITY",
    "AlphaBetaSensorSettings",
    "AlphaBetaSensors",
    "DiscretisationWarning",
    "FitResult",
    "KalmanResult",
    "KalmanSensors",
    "SweepResult",
    "fit",
    "ins_run",
    "sweep",
    "__version__",
    "altitude_to_pressure",
    "pressure_to_altitude",
    "vertical_acceleration",
]
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
