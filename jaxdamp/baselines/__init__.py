"""The conventional ways to get a damper's numbers, as public functions: quasi-static time marching
with incremental return mapping, HBM-AFT at a prescribed amplitude (on the in-phase path,
`hbm_aft`, and on any path, both dampers, pads that open: `hbm_aft_path`), and a
tanh-regularised friction law evaluated the HBM-AFT way; a lumped bladed disk (`lumped_disk`)
and its whole ring with explicit dampers integrated in time (`ring`), the check of the cyclic
reduction. They check the direct method and are timed against it (`benchmarks/`). They import the core; the core never imports them.
"""

from .hbm import HBMResult as HBMResult
from .hbm import first_harmonic as first_harmonic
from .hbm import hbm_aft as hbm_aft
from .regularized import regularized_aft as regularized_aft
from .timemarch import MarchModel as MarchModel
from .timemarch import TimeMarchResult as TimeMarchResult
from .timemarch import march as march
from .timemarch import march_model as march_model
from .timemarch import time_march as time_march
from .hbm import hbm_aft_kernel as hbm_aft_kernel
from .regularized import regularized_aft_kernel as regularized_aft_kernel
from .timemarch import time_march_kernel as time_march_kernel
from .ellipse_march import EllipseMarch as EllipseMarch
from .ellipse_march import march_ellipse as march_ellipse
from .hbm_path import HBMPathResult as HBMPathResult
from .hbm_path import hbm_aft_path as hbm_aft_path
from .hbm_path import hbm_aft_path_kernel as hbm_aft_path_kernel
from .lumped_disk import LumpedDisk as LumpedDisk
from .lumped_disk import full_matrices as full_matrices
from .lumped_disk import modal_family as modal_family
from .lumped_disk import sector_matrices as sector_matrices
from .ring import RingResponse as RingResponse
from .ring import ring_response as ring_response


__all__ = ["HBMResult", "first_harmonic", "hbm_aft", "regularized_aft", "MarchModel",
           "TimeMarchResult", "march", "march_model", "time_march", "hbm_aft_kernel",
           "regularized_aft_kernel", "time_march_kernel", "EllipseMarch", "march_ellipse",
           "HBMPathResult", "hbm_aft_path", "hbm_aft_path_kernel",
           "LumpedDisk", "full_matrices", "modal_family", "sector_matrices", "RingResponse",
           "ring_response"]
