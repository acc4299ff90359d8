"""Type stubs for the Cython binding of csrc/fusion_altitude_sweep.h (used by fusion_altitude.sweep)."""

from typing import Optional, Sequence, Tuple

import numpy as np

BLOCK: int

def run(accel: np.ndarray, baro_altitude: np.ndarray, dt: np.ndarray, dt_is_array: bool, gains: np.ndarray,
        k_start: int, k_stop: int, state: np.ndarray, outputs: Optional[Sequence[np.ndarray]],
        metrics: Optional[Sequence[np.ndarray]], reference: Optional[np.ndarray],
        mask: Optional[np.ndarray]) -> Tuple[int, int, int]: ...
