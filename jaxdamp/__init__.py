"""jaxdamp: underplatform damper Base-Cycles by the direct piecewise-linear method, in JAX.

Float64 matters here: call `jaxdamp.enable_x64()` (or set JAX_ENABLE_X64=1) before computing; the
public entry points refuse to run in float32. Importing the library changes no JAX configuration
and imports no plotting library. Layers (docs/architecture.md): this package's core modules, then
`jaxdamp.baselines` and `jaxdamp.paper`, then `jaxdamp.plotting`, then `jaxdamp.cli`.

Contents by concept (units: psi in mrad, k in N mm/mrad, forces in N, stiffness in N/mm;
docs/api.md maps each concept to its functions and says what a wrong input gets):

- Inputs: `Design` (shape, mu, contacts, load as one pytree), `check_design` and `check_batch`
  (the one input boundary of a design and of a batch: every entry point checks through it before
  anything is traced), `DamperShape`, `family_shape`, `FAMILY`, `paper_tables`, `Contacts`,
  `LoadCase`, `REFERENCE_KN`, `REFERENCE_KT`.
- Status: `RESULTS`, the one status code every result carries, combined in one order
  (`RESULTS.first`, `combine`, `worst`; `jaxdamp.status.SEVERITY`); `Float64Required`;
  `SmallRotationWarning`.
- Statics: `full_slip_statics`, `design_br` (the paper's b_R rule), `full_slip_work_shape_factors`.
- The Base-Cycle: `base_cycle`, `five_numbers`, `cycle_numbers` (the same numbers, one design
  fast, no cycle kept), `complex_stiffness`, `contact_energies`, `work_shape_factors`, `moment`,
  `transitions_chart` (the contact-state chart of any cycle).
- One steady cycle: `amplitude_cycle` (in-phase and straight paths), `elliptic_cycle`,
  `path_base_cycle`, `interblade_sweep`; motions: `Motion`, `in_phase_motion`,
  `interblade_motion`, `straight_motion`, `general_motion`.
- k(psi_a) curves: `amplitude_curves` (method "cycles" or "sequence"), `stiffness_curve` (the
  pieces whose loop corners are affine in psi_a, from a few exact cycles).
- Bands over histories: `amplitude_band` (one amplitude, or a grid).
- Many designs: `stack_designs`, `evaluate_designs` (the numbers), `base_cycles` (the cycles),
  `sweep`, `map_batched`.
- Derivatives: `five_numbers_jacobian`, `k_im_gradient_at`, `batch_jacobian`; of a path cycle
  with respect to the design and the path: `path_gradient`.
- Forced response: `BladeMode`, `damper_stiffness`, `response_curves`, `design_peaks`,
  `peak_response`, `peak_band`, `frf`, `designer_diagram`; on a platform path:
  `path_response_curves`; the blade row from modal data: `ModalFamily`, `nodal_scene`,
  `row_response`, `row_band`, `row_gradient` (the peaks' derivatives), `row_diagram` (the worst
  peak against the force and F_D), `engine_orders_of` (files: `jaxdamp.modal_file`).
- Measured loops: `fit_loops`, `sample_loop`.
- Uncertain contacts: `Uncertainty`, `sample_scenarios`, `peak_distribution`.
- Building blocks: `jaxdamp.blocks` (the section's geometry, a half-cycle, one full-slip end, the
  admissible polytope, the response's stiffness constructors, validated ranges, one-part checks).

Every `*_kernel` is the unchecked, traceable form of its entry point (traced under
`jax.eval_shape` and `vmap` by tests/test_kernel_contract.py): call it inside your own jit, vmap
or grad. Host-driven unchecked forms are named `*_unchecked`.
"""

__version__ = "0.2.0"


# Inputs: the design as one pytree
import warnings

import jax

from .design import Design as Design
from .design import check_design as check_design
from .design import check_batch as check_batch
from .geometry import DamperShape as DamperShape
from .geometry import family_shape as family_shape
from .geometry import FAMILY as FAMILY
from .geometry import paper_tables as paper_tables
from .params import Contacts as Contacts
from .params import LoadCase as LoadCase
from .params import REFERENCE_KN as REFERENCE_KN
from .params import REFERENCE_KT as REFERENCE_KT

# Status and float64
from .status import RESULTS as RESULTS
from ._validate import Float64Required as Float64Required
from .conventions import SmallRotationWarning as SmallRotationWarning

# Full-slip statics and the b_R design rule
from .statics import FullSlipStatics as FullSlipStatics
from .statics import full_slip_statics as full_slip_statics
from .statics import statics_kernel as statics_kernel
from .statics import DesignResult as DesignResult
from .statics import design_br as design_br
from .statics import full_slip_work_shape_factors as full_slip_work_shape_factors

# The Base-Cycle (direct piecewise-linear method) and its numbers
from .cycle import BaseCycle as BaseCycle
from .cycle import base_cycle as base_cycle
from .cycle import base_cycle_kernel as base_cycle_kernel
from .charts import transitions_chart as transitions_chart
from .harmonics import FiveNumbers as FiveNumbers
from .harmonics import five_numbers as five_numbers
from .harmonics import five_numbers_kernel as five_numbers_kernel
from .harmonics import CycleNumbers as CycleNumbers
from .harmonics import cycle_numbers as cycle_numbers
from .harmonics import complex_stiffness as complex_stiffness
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
from .ellipse import elliptic_kernel as elliptic_kernel
from .path_base_cycle import PathBaseCycle as PathBaseCycle
from .path_base_cycle import path_base_cycle as path_base_cycle
from .path_base_cycle import path_base_cycle_kernel as path_base_cycle_kernel
from .amplitude import AmplitudeCycle as AmplitudeCycle
from .amplitude import amplitude_cycle as amplitude_cycle
from .amplitude import amplitude_kernel as amplitude_kernel
from .curves import StiffnessCurves as StiffnessCurves
from .sequence import amplitude_curves as amplitude_curves
from .curves import curves_kernel as curves_kernel
from .band import Band as Band
from .band import amplitude_band as amplitude_band
from .band import amplitude_bands as _amplitude_bands
from .sequence import StiffnessCurve as StiffnessCurve
from .sequence import stiffness_curve as stiffness_curve
from .sequence import sequence_curves as _sequence_curves

# Many designs: the one batching path
from .batch import stack_designs as stack_designs
from .batch import map_batched as map_batched
from .batch import base_cycles as base_cycles
from .batch import evaluate_designs as evaluate_designs
from .batch import DesignSummary as DesignSummary
from .batch import sweep as sweep
from .batch import SweepResult as SweepResult

# Derivatives
from .gradients import FiveNumbersJacobian as FiveNumbersJacobian
from .gradients import five_numbers_jacobian as five_numbers_jacobian
from .gradients import KImGradient as KImGradient
from .gradients import k_im_gradient_at as k_im_gradient_at
from .gradients import batch_jacobian as batch_jacobian
from .path_gradients import PathGradient as PathGradient
from .path_gradients import path_gradient as path_gradient

# Blade forced response (one mode, the damper as a complex spring)
from .response import BladeMode as BladeMode
from .response import DamperStiffness as DamperStiffness
from .response import damper_stiffness as damper_stiffness
from .response import damper_stiffness_kernel as damper_stiffness_kernel
from .response import FRF as FRF
from .response import frf as frf
from .response import Peaks as Peaks
from .response import peak_response as peak_response
from .response import design_peaks as design_peaks
from .response import peak_band as peak_band
from .response import ResponseCurves as ResponseCurves
from .response import response_curves as response_curves
from .response import path_response_curves as path_response_curves
from .response import DesignerDiagram as DesignerDiagram
from .response import designer_diagram as designer_diagram
from .response import ModalFamily as ModalFamily
from .response import NodalScene as NodalScene
from .response import nodal_scene as nodal_scene
from .response import RowResponse as RowResponse
from .response import row_response as row_response
from .response import row_band as row_band
from .response import RowGradient as RowGradient
from .response import row_gradient as row_gradient
from .response import RowBand as RowBand
from .response import RowDiagram as RowDiagram
from .response import row_diagram as row_diagram
from .response import engine_orders_of as engine_orders_of
from .response import path_cycle_kernel as path_cycle_kernel

# Contact parameters from measured loops
from .fit import LoopFit as LoopFit
from .fit import fit_loops as fit_loops
from .fit import sample_loop as sample_loop

# Uncertain contacts (Monte Carlo over the peak)
from .uncertainty import Uncertainty as Uncertainty
from .uncertainty import Scenarios as Scenarios
from .uncertainty import PeakDistribution as PeakDistribution
from .uncertainty import sample_scenarios as sample_scenarios
from .uncertainty import peak_distribution as peak_distribution
from .uncertainty import magnification_kernel as magnification_kernel

# Constrained optimisation building block (optax style)


# The building blocks behind the entry points (jaxdamp.blocks): a namespace of their own
from . import blocks as blocks

# Names that moved or merged: still found here, with a DeprecationWarning saying where they went
# (CHANGELOG, 0.3.0). Removed in 0.4.
_MOVED_TO_BLOCKS = frozenset(blocks.__all__)
_MERGED = {
    "HalfCycle": ("jaxdamp.blocks.Half", lambda: blocks.Half),
    "sequence_curves": ("jaxdamp.amplitude_curves(..., method='sequence')",
                        lambda: _sequence_curves),
    "amplitude_bands": ("jaxdamp.amplitude_band with a grid of amplitudes", lambda: _amplitude_bands),
    "elliptic_transitions_chart": ("jaxdamp.transitions_chart", lambda: transitions_chart),
}


def __getattr__(name: str):
    if name in _MOVED_TO_BLOCKS or name in _MERGED:
        _deprecated(name)
    if name in _MOVED_TO_BLOCKS:
        return getattr(blocks, name)
    if name in _MERGED:
        return _MERGED[name][1]()
    raise AttributeError(f"module 'jaxdamp' has no attribute {name!r}")


def _deprecated(name: str) -> None:
    where = f"jaxdamp.blocks.{name}" if name in _MOVED_TO_BLOCKS else _MERGED[name][0]
    warnings.warn(f"jaxdamp.{name} is deprecated: use {where} (docs/api.md; removed in 0.4)",
                  DeprecationWarning, stacklevel=3)


def enable_x64() -> None:
    """Switch JAX to float64 (the library's results are specified in float64)."""
    jax.config.update("jax_enable_x64", True)


__all__ = ["__version__", "enable_x64", "Design", "check_design", "check_batch", "DamperShape",
           "family_shape", "FAMILY", "paper_tables", "Contacts", "LoadCase", "REFERENCE_KN",
           "REFERENCE_KT", "RESULTS", "Float64Required", "SmallRotationWarning", "FullSlipStatics",
           "full_slip_statics", "statics_kernel", "DesignResult", "design_br",
           "full_slip_work_shape_factors", "BaseCycle", "base_cycle", "base_cycle_kernel",
           "transitions_chart", "FiveNumbers", "five_numbers", "five_numbers_kernel",
           "CycleNumbers", "cycle_numbers", "complex_stiffness", "moment", "CycleEnergy",
           "WorkShapeFactors", "contact_energies", "work_shape_factors", "Motion",
           "in_phase_motion", "interblade_motion", "straight_motion", "general_motion",
           "EllipticCycle", "elliptic_cycle", "interblade_sweep", "elliptic_kernel",
           "PathBaseCycle", "path_base_cycle", "path_base_cycle_kernel", "AmplitudeCycle",
           "amplitude_cycle", "amplitude_kernel", "StiffnessCurves", "amplitude_curves",
           "curves_kernel", "Band", "amplitude_band", "StiffnessCurve", "stiffness_curve",
           "stack_designs", "map_batched", "base_cycles", "evaluate_designs", "DesignSummary",
           "sweep", "SweepResult", "FiveNumbersJacobian", "five_numbers_jacobian", "KImGradient",
           "k_im_gradient_at", "batch_jacobian", "path_gradient", "PathGradient", "BladeMode", "DamperStiffness",
           "damper_stiffness", "damper_stiffness_kernel", "FRF", "frf", "Peaks", "peak_response",
           "design_peaks", "peak_band", "ResponseCurves", "response_curves",
           "path_response_curves", "DesignerDiagram", "ModalFamily", "NodalScene", "nodal_scene",
           "RowResponse", "row_response", "row_band", "RowBand", "RowGradient", "row_gradient",
           "RowDiagram", "row_diagram", "engine_orders_of",
           "path_cycle_kernel", "designer_diagram", "Uncertainty", "Scenarios", "PeakDistribution",
           "sample_scenarios", "peak_distribution", "magnification_kernel", "LoopFit", "fit_loops",
           "sample_loop"]
