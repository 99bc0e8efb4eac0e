"""jaxdamp: underplatform damper Base-Cycles by the direct piecewise-linear method, in JAX.

Float64 matters here: call `jaxdamp.enable_x64()` (or set JAX_ENABLE_X64=1) before computing; the
public entry points refuse to run in float32. Importing the library changes no JAX configuration
and imports no plotting library. Layers (docs/architecture.md): this package's core modules, then
`jaxdamp.baselines` and `jaxdamp.paper`, then `jaxdamp.plotting`, then `jaxdamp.cli`.
"""

__version__ = "0.2.0"

from ._validate import Float64Required as Float64Required
from .amplitude import AmplitudeCycle as AmplitudeCycle
from .amplitude import StiffnessCurves as StiffnessCurves
from .amplitude import amplitude_curves as amplitude_curves
from .amplitude import amplitude_cycle as amplitude_cycle
from .amplitude import amplitude_kernel as amplitude_kernel
from .amplitude import curves_kernel as curves_kernel
from .band import Band as Band
from .band import amplitude_band as amplitude_band
from .batch import DesignSummary as DesignSummary
from .batch import SweepResult as SweepResult
from .batch import centred_br as centred_br
from .batch import evaluate_designs as evaluate_designs
from .batch import stack_designs as stack_designs
from .batch import sweep as sweep
from .cycle import BaseCycle as BaseCycle
from .cycle import HalfCycle as HalfCycle
from .cycle import base_cycle as base_cycle
from .cycle import base_cycle_kernel as base_cycle_kernel
from .batch import base_cycles as base_cycles
from .batch import map_batched as map_batched
from .batch import default_chunk as default_chunk
from .cycle import transitions_chart as transitions_chart
from .design import Design as Design
from .energy import CycleEnergy as CycleEnergy
from .energy import WorkShapeFactors as WorkShapeFactors
from .energy import contact_energies as contact_energies
from .energy import work_shape_factors as work_shape_factors
from .geometry import CONTACT_NAMES as CONTACT_NAMES
from .geometry import FAMILY as FAMILY
from .geometry import DamperShape as DamperShape
from .geometry import SectionGeometry as SectionGeometry
from .geometry import family_shape as family_shape
from .geometry import paper_tables as paper_tables
from .geometry import section_geometry as section_geometry
from .fit import LoopFit as LoopFit
from .fit import fit_loops as fit_loops
from .gradients import FiveNumbersJacobian as FiveNumbersJacobian
from .gradients import KImGradient as KImGradient
from .gradients import batch_jacobian as batch_jacobian
from .gradients import five_numbers_jacobian as five_numbers_jacobian
from .gradients import k_im_gradient_at as k_im_gradient_at
from .harmonics import SMALL_ROTATION_MRAD as SMALL_ROTATION_MRAD
from .harmonics import FiveNumbers as FiveNumbers
from .harmonics import SmallRotationWarning as SmallRotationWarning
from .harmonics import CycleNumbers as CycleNumbers
from .harmonics import complex_stiffness as complex_stiffness
from .harmonics import cycle_numbers as cycle_numbers
from .harmonics import cycle_work as cycle_work
from .harmonics import five_numbers as five_numbers
from .harmonics import five_numbers_kernel as five_numbers_kernel
from .harmonics import moment as moment
from .params import REFERENCE_KN as REFERENCE_KN
from .params import REFERENCE_KT as REFERENCE_KT
from .params import Contacts as Contacts
from .params import LoadCase as LoadCase
from .statics import DesignResult as DesignResult
from .statics import FullSlipState as FullSlipState
from .statics import FullSlipStatics as FullSlipStatics
from .statics import design_br as design_br
from .statics import full_slip_state as full_slip_state
from .statics import full_slip_statics as full_slip_statics
from .statics import full_slip_work_shape_factors as full_slip_work_shape_factors
from .statics import statics_kernel as statics_kernel
from .status import RESULTS as RESULTS


def enable_x64() -> None:
    """Switch JAX to float64 (the library's results are specified in float64)."""
    import jax

    jax.config.update("jax_enable_x64", True)
