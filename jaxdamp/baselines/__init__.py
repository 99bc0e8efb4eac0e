"""Conventional baseline solvers (time marching, HBM-AFT, tanh-regularised HBM-AFT), public API.

Re-exports only; on main this package holds the modules themselves.
"""

from ..hbm import hbm_aft as hbm_aft
from ..regularized import regularized_aft as regularized_aft
from ..timemarch import time_march as time_march

__all__ = ["time_march", "hbm_aft", "regularized_aft"]
