"""Type stub of the CSV row formatter (``_csv_format.pyx``), written by hand: it is not an estimator binding."""

import numpy as np
import numpy.typing as npt

#: Column kinds: "%r" (float64, shortest round trip), "%.9g" (float32), "%d" (integers and booleans).
KIND_REPR: int
KIND_G9: int
KIND_INT: int

def format_rows(block: npt.NDArray[np.float64], kinds: npt.NDArray[np.int32]) -> bytes: ...
