"""jaxdamp: underplatform damper Base-Cycles by the direct piecewise-linear method, in JAX.

Float64 matters here: call `jaxdamp.enable_x64()` (or set JAX_ENABLE_X64=1) before computing.
Importing the library does not change JAX's global configuration.
"""

from .batch import (Designs, DesignSummary, SweepResult, centred_br, evaluate_designs,
                    stack_designs, sweep)
from .calibration import (CalibrationResult, CalibrationTargets, calibrate, comparison_table,
                          paper_targets)
from .cycle import BaseCycle, HalfCycle, base_cycle, base_cycles, transitions_chart
from .energy import CycleEnergy, WorkShapeFactors, contact_energies, work_shape_factors
from .geometry import (CONTACT_NAMES, FAMILY, DamperShape, SectionGeometry, family_shape,
                       paper_tables, section_geometry)
from .gradients import (DesignVariables, FiveNumbersJacobian, KImGradient, batch_jacobian,
                        five_numbers_jacobian, k_im_gradient_at)
from .harmonics import FiveNumbers, complex_stiffness, cycle_work, five_numbers, moment
from .params import REFERENCE_KN, REFERENCE_KT, Contacts, LoadCase
from .statics import (DesignResult, FullSlipState, FullSlipStatics, design_br, full_slip_state,
                      full_slip_statics, full_slip_work_shape_factors)


def enable_x64() -> None:
    """Switch JAX to float64 (the library's results are specified in float64)."""
    import jax

    jax.config.update("jax_enable_x64", True)


__all__ = [name for name in dir() if not name.startswith("_")]
