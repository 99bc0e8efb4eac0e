"""The building blocks behind jaxdamp's entry points, for users who compose their own programs.

`import jaxdamp` gives the library by concept (docs/api.md); this module holds what those
functions are made of and what a program of one's own may need besides: the section's geometry,
the tract engine's half-cycle, the statics of one full-slip end, the admissible polytope, the
response's stiffness constructors, the constants of the validated ranges, and the one-part input
checks that `jaxdamp.check_design` combines. Everything here is traceable where it computes
(jit, vmap, grad) and checks concrete inputs where it is given them.
"""

# The section and its pads
from .geometry import SectionGeometry as SectionGeometry
from .geometry import section_geometry as section_geometry
from .geometry import pad_names as pad_names
from .geometry import CONTACT_NAMES as CONTACT_NAMES
from .geometry import platform_moment as platform_moment

# Ranges the model is validated in, and the one-part input checks
from .params import VALIDATED_STIFFNESS_OVER_FD_PER_MM as VALIDATED_STIFFNESS_OVER_FD_PER_MM
from .params import VALIDATED_KT_OVER_KN as VALIDATED_KT_OVER_KN
from .params import validated_range_violations as validated_range_violations
from .params import validate_mu as validate_mu
from .params import validate_contacts as validate_contacts
from .params import validate_load as validate_load
from .conventions import SMALL_ROTATION_MRAD as SMALL_ROTATION_MRAD
from .response import validate_mode as validate_mode
from .response import validate_family as validate_family

# Statics of one full-slip end; the tract engine's half-cycle
from .statics import FullSlipState as FullSlipState
from .statics import full_slip_state as full_slip_state
from .half import Half as Half
from .half import run_half as run_half
from .harmonics import cycle_work as cycle_work

# The admissible states of the band; a curve's pieces
from .admissible import admissible_polytope as admissible_polytope
from .admissible import polytope_vertices as polytope_vertices
from .sequence import curve_at as curve_at

# Batching
from .batch import default_chunk as default_chunk
from .batch import centred_br as centred_br

# The forced response's pieces: damper stiffness constructors, FRF grids, scenes
from .response import frf_amplitude_grid as frf_amplitude_grid
from .response import linear_frf as linear_frf
from .response import tabulated_stiffness as tabulated_stiffness
from .response import register_stiffness_method as register_stiffness_method
from .response import no_damper as no_damper
from .response import stuck_damper as stuck_damper
from .response import scaled_stiffness as scaled_stiffness
from .response import DIAGRAM_MUS as DIAGRAM_MUS
from .response import prepare_scene as prepare_scene
from .response import path_damper as path_damper

# The loop fit's least-squares problem
from .fit import fit_problem as fit_problem

__all__ = ["SectionGeometry", "section_geometry", "pad_names", "CONTACT_NAMES", "platform_moment",
           "VALIDATED_STIFFNESS_OVER_FD_PER_MM", "VALIDATED_KT_OVER_KN",
           "validated_range_violations", "validate_mu", "validate_contacts", "validate_load",
           "SMALL_ROTATION_MRAD", "validate_mode", "validate_family", "FullSlipState",
           "full_slip_state", "Half", "run_half", "cycle_work", "admissible_polytope",
           "polytope_vertices", "curve_at", "default_chunk", "centred_br", "frf_amplitude_grid",
           "linear_frf", "tabulated_stiffness", "register_stiffness_method", "no_damper",
           "stuck_damper", "scaled_stiffness", "DIAGRAM_MUS", "prepare_scene", "path_damper",
           "fit_problem"]
