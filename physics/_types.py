"""Array type aliases used in signatures. Shapes are given in each docstring."""

import numpy as np
from numpy.typing import NDArray

Vec3 = NDArray[np.float64]  # (3,)
Mat3 = NDArray[np.float64]  # (3, 3)
Array = NDArray[np.float64]  # any shape, stated in the docstring
