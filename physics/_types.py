"""Array type aliases used in signatures. Shapes are given in each docstring."""

from numpy.typing import NDArray
import numpy as np

Vec3 = NDArray[np.float64]  # (3,)
Mat3 = NDArray[np.float64]  # (3, 3)
Array = NDArray[np.float64]  # any shape, stated in the docstring
