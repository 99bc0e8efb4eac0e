"""jaxdamp: underplatform damper Base-Cycles by the direct piecewise-linear method, in JAX.

Float64 matters here: call `jaxdamp.enable_x64()` (or set JAX_ENABLE_X64=1) before computing; the
public entry points refuse to run in float32. Importing the library changes no JAX configuration
and imports no plotting library. Layers (docs/architecture.md): this package's core modules, then
`jaxdamp.baselines` and `jaxdamp.paper`, then `jaxdamp.plotting`, then `jaxdamp.cli`.

Contents (units: psi in mrad, k in N mm/mrad, forces in N, stiffness in N/mm):

- Inputs: `Design` (shape, mu, contacts, load as one pytree), `check_design` and `check_batch`
  (the one input boundary of a design and of a batch: every entry point checks through it before
  anything is traced), `DamperShape`, `family_shape`,
  `Contacts`, `LoadCase`, the validated stiffness range (`validated_range_violations`: the limits
  a contact pair leaves, as text).
- Status: `RESULTS`, the one status code every result carries; `Float64Required`;
  `SmallRotationWarning`.
- Statics: `full_slip_statics`, `design_br` (the paper's b_R rule).
- The Base-Cycle: `base_cycle`, `five_numbers`, `cycle_numbers`, `complex_stiffness`,
  `contact_energies`, `work_shape_factors`, `transitions_chart`.
- Any amplitude: `amplitude_cycle`, `amplitude_curves`, `amplitude_band` (`amplitude_bands`: a grid); `stiffness_curve`
  (k(psi_a) as pieces whose loop corners are affine in psi_a, from a few exact cycles).
- Many designs: `stack_designs`, `evaluate_designs`, `base_cycles`, `sweep`, `map_batched`.
- Derivatives: `five_numbers_jacobian`, `k_im_gradient_at`, `batch_jacobian`.
- Forced response: `BladeMode`, `damper_stiffness`, `response_curves`, `design_peaks`,
  `peak_response`, `peak_band`, `frf`, `designer_diagram`; on a platform path (`Motion`):
  `path_response_curves`; across a blade row from modal data:
  `ModalFamily`, `nodal_scene`, `row_response`, `row_band` (files: `jaxdamp.modal_file`).
- Measured loops: `fit_loops` (mu, kn, kt with intervals from moment or contact loops).
- Uncertain contacts: `Uncertainty`, `sample_scenarios`, `peak_distribution`.

Every `*_kernel` is the unchecked, traceable form of its entry point: call it inside your own
jit, vmap or grad.
"""

__version__ = "0.2.0"


# Inputs: the design as one pytree
import jax

from .design import Design as Design
from .design import check_design as check_design
from .design import check_batch as check_batch
from .geometry import DamperShape as DamperShape
from .geometry import SectionGeometry as SectionGeometry
from .geometry import section_geometry as section_geometry
from .geometry import family_shape as family_shape
from .geometry import pad_names as pad_names
from .geometry import FAMILY as FAMILY
from .geometry import CONTACT_NAMES as CONTACT_NAMES
from .geometry import paper_tables as paper_tables
from .geometry import platform_moment as platform_moment
from .params import Contacts as Contacts
from .params import LoadCase as LoadCase
from .params import REFERENCE_KN as REFERENCE_KN
from .params import REFERENCE_KT as REFERENCE_KT
from .params import validate_mu as validate_mu
from .params import validate_contacts as validate_contacts
from .params import validate_load as validate_load
from .params import VALIDATED_STIFFNESS_OVER_FD_PER_MM as VALIDATED_STIFFNESS_OVER_FD_PER_MM
from .params import VALIDATED_KT_OVER_KN as VALIDATED_KT_OVER_KN
from .params import validated_range_violations as validated_range_violations

# Status and float64
from .status import RESULTS as RESULTS
from ._validate import Float64Required as Float64Required
from .conventions import SMALL_ROTATION_MRAD as SMALL_ROTATION_MRAD
from .conventions import SmallRotationWarning as SmallRotationWarning

# Full-slip statics and the b_R design rule
from .statics import FullSlipStatics as FullSlipStatics
from .statics import FullSlipState as FullSlipState
from .statics import full_slip_statics as full_slip_statics
from .statics import full_slip_state as full_slip_state
from .statics import statics_kernel as statics_kernel
from .statics import DesignResult as DesignResult
from .statics import design_br as design_br
from .statics import full_slip_work_shape_factors as full_slip_work_shape_factors

# The Base-Cycle (direct piecewise-linear method) and its numbers
from .cycle import BaseCycle as BaseCycle
from .half import Half as Half
from .half import run_half as run_half
from .cycle import HalfCycle as HalfCycle  # the old name of Half
from .cycle import base_cycle as base_cycle
from .cycle import base_cycle_kernel as base_cycle_kernel
from .cycle import transitions_chart as transitions_chart
from .harmonics import FiveNumbers as FiveNumbers
from .harmonics import five_numbers as five_numbers
from .harmonics import five_numbers_kernel as five_numbers_kernel
from .harmonics import CycleNumbers as CycleNumbers
from .harmonics import cycle_numbers as cycle_numbers
from .harmonics import complex_stiffness as complex_stiffness
from .harmonics import cycle_work as cycle_work
from .harmonics import moment as moment
from .energy import CycleEnergy as CycleEnergy
from .energy import WorkShapeFactors as WorkShapeFactors
from .energy import contact_energies as contact_energies
from .energy import work_shape_factors as work_shape_factors

# Exact cycles at any amplitude, and the band over histories
from .motion import Motion as Motion
from .motion import in_phase_motion as in_phase_motion
from .motion import interblade_motion as interblade_motion
from .motion import straight_motion as straight_motion
from .motion import general_motion as general_motion
from .ellipse import EllipticCycle as EllipticCycle
from .ellipse import elliptic_cycle as elliptic_cycle
from .ellipse import interblade_sweep as interblade_sweep
from .ellipse import elliptic_transitions_chart as elliptic_transitions_chart
from .ellipse import elliptic_kernel as elliptic_kernel
from .path_base_cycle import PathBaseCycle as PathBaseCycle
from .path_base_cycle import path_base_cycle as path_base_cycle
from .path_base_cycle import path_base_cycle_kernel as path_base_cycle_kernel
from .amplitude import AmplitudeCycle as AmplitudeCycle
from .amplitude import amplitude_cycle as amplitude_cycle
from .amplitude import amplitude_kernel as amplitude_kernel
from .curves import StiffnessCurves as StiffnessCurves
from .curves import amplitude_curves as amplitude_curves
from .curves import curves_kernel as curves_kernel
from .band import Band as Band
from .band import amplitude_band as amplitude_band
from .band import amplitude_bands as amplitude_bands
from .admissible import admissible_polytope as admissible_polytope
from .admissible import polytope_vertices as polytope_vertices
from .sequence import StiffnessCurve as StiffnessCurve
from .sequence import curve_at as curve_at
from .sequence import sequence_curves as sequence_curves
from .sequence import stiffness_curve as stiffness_curve

# Many designs: the one batching path
from .batch import stack_designs as stack_designs
from .batch import map_batched as map_batched
from .batch import default_chunk as default_chunk
from .batch import base_cycles as base_cycles
from .batch import evaluate_designs as evaluate_designs
from .batch import DesignSummary as DesignSummary
from .batch import sweep as sweep
from .batch import SweepResult as SweepResult
from .batch import centred_br as centred_br

# Derivatives
from .gradients import FiveNumbersJacobian as FiveNumbersJacobian
from .gradients import five_numbers_jacobian as five_numbers_jacobian
from .gradients import KImGradient as KImGradient
from .gradients import k_im_gradient_at as k_im_gradient_at
from .gradients import batch_jacobian as batch_jacobian

# Blade forced response (one mode, the damper as a complex spring)
from .response import BladeMode as BladeMode
from .response import validate_mode as validate_mode
from .response import DamperStiffness as DamperStiffness
from .response import damper_stiffness as damper_stiffness
from .response import damper_stiffness_kernel as damper_stiffness_kernel
from .response import stuck_damper as stuck_damper
from .response import no_damper as no_damper
from .response import scaled_stiffness as scaled_stiffness
from .response import tabulated_stiffness as tabulated_stiffness
from .response import register_stiffness_method as register_stiffness_method
from .response import FRF as FRF
from .response import frf as frf
from .response import frf_amplitude_grid as frf_amplitude_grid
from .response import linear_frf as linear_frf
from .response import Peaks as Peaks
from .response import peak_response as peak_response
from .response import design_peaks as design_peaks
from .response import peak_band as peak_band
from .response import ResponseCurves as ResponseCurves
from .response import response_curves as response_curves
from .response import path_response_curves as path_response_curves
from .response import DesignerDiagram as DesignerDiagram
from .response import designer_diagram as designer_diagram
from .response import DIAGRAM_MUS as DIAGRAM_MUS
from .response import ModalFamily as ModalFamily
from .response import NodalScene as NodalScene
from .response import validate_family as validate_family
from .response import nodal_scene as nodal_scene
from .response import RowResponse as RowResponse
from .response import row_response as row_response
from .response import row_band as row_band
from .response import RowBand as RowBand
from .response import engine_orders_of as engine_orders_of
from .response import path_damper as path_damper
from .response import path_cycle_kernel as path_cycle_kernel
from .response import prepare_scene as prepare_scene

# Contact parameters from measured loops
from .fit import LoopFit as LoopFit
from .fit import fit_loops as fit_loops
from .fit import fit_problem as fit_problem
from .fit import sample_loop as sample_loop

# Uncertain contacts (Monte Carlo over the peak)
from .uncertainty import Uncertainty as Uncertainty
from .uncertainty import Scenarios as Scenarios
from .uncertainty import PeakDistribution as PeakDistribution
from .uncertainty import sample_scenarios as sample_scenarios
from .uncertainty import peak_distribution as peak_distribution
from .uncertainty import magnification_kernel as magnification_kernel

# Constrained optimisation building block (optax style)


def enable_x64() -> None:
    """Switch JAX to float64 (the library's results are specified in float64)."""
    jax.config.update("jax_enable_x64", True)


__all__ = ["__version__", "enable_x64", "Design", "check_design", "check_batch", "DamperShape", "SectionGeometry",
           "section_geometry", "family_shape", "pad_names", "FAMILY", "CONTACT_NAMES", "paper_tables",
           "platform_moment", "Contacts", "LoadCase", "REFERENCE_KN", "REFERENCE_KT",
           "validate_mu", "validate_contacts", "validate_load",
           "VALIDATED_STIFFNESS_OVER_FD_PER_MM", "VALIDATED_KT_OVER_KN",
           "validated_range_violations", "RESULTS", "Float64Required", "SMALL_ROTATION_MRAD",
           "SmallRotationWarning", "FullSlipStatics", "FullSlipState", "full_slip_statics",
           "full_slip_state", "statics_kernel", "DesignResult", "design_br",
           "full_slip_work_shape_factors", "BaseCycle", "Half", "run_half", "HalfCycle", "base_cycle",
           "base_cycle_kernel", "transitions_chart", "FiveNumbers", "five_numbers",
           "five_numbers_kernel", "CycleNumbers", "cycle_numbers", "complex_stiffness",
           "cycle_work", "moment", "CycleEnergy", "WorkShapeFactors", "contact_energies",
           "work_shape_factors", "Motion", "in_phase_motion", "interblade_motion",
           "straight_motion", "general_motion", "EllipticCycle", "elliptic_cycle", "interblade_sweep",
           "elliptic_transitions_chart",
           "elliptic_kernel", "PathBaseCycle", "path_base_cycle", "path_base_cycle_kernel",
           "AmplitudeCycle", "amplitude_cycle", "amplitude_kernel",
           "StiffnessCurves", "amplitude_curves", "curves_kernel", "Band", "amplitude_band",
           "amplitude_bands", "admissible_polytope", "polytope_vertices", "StiffnessCurve",
           "curve_at", "sequence_curves", "stiffness_curve", "stack_designs", "map_batched",
           "default_chunk", "base_cycles", "evaluate_designs", "DesignSummary", "sweep",
           "SweepResult", "centred_br", "FiveNumbersJacobian", "five_numbers_jacobian",
           "KImGradient", "k_im_gradient_at", "batch_jacobian", "BladeMode", "validate_mode",
           "DamperStiffness", "damper_stiffness", "damper_stiffness_kernel", "stuck_damper",
           "no_damper", "scaled_stiffness", "tabulated_stiffness", "register_stiffness_method",
           "FRF", "frf", "frf_amplitude_grid", "linear_frf", "Peaks", "peak_response",
           "design_peaks", "peak_band", "ResponseCurves", "response_curves", "path_response_curves",
           "DesignerDiagram",
           "ModalFamily", "NodalScene", "validate_family", "nodal_scene", "RowResponse",
           "row_response", "row_band", "RowBand", "engine_orders_of", "path_damper", "path_cycle_kernel", "prepare_scene",
           "designer_diagram", "DIAGRAM_MUS", "Uncertainty", "Scenarios", "PeakDistribution",
           "sample_scenarios", "peak_distribution", "magnification_kernel", "LoopFit", "fit_loops",
           "fit_problem", "sample_loop"]
