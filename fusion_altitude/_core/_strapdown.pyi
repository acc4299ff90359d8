"""Type stub of the strapdown integration loop (``_strapdown.pyx``), written by hand: it is not an estimator binding."""

import numpy as np
import numpy.typing as npt

def integrate_steps(initial: npt.ArrayLike, steps: npt.ArrayLike) -> npt.NDArray[np.float64]: ...
