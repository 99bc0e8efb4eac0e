"""Blade forced response from the damper's complex stiffness (the Platform Centred Reduction).

One blade-dominated mode of a tuned bladed disk at one interblade phase angle, reduced to the tip
displacement amplitude A (mm). The damper is a complex spring between the platforms: at platform
rotation amplitude psi_a = r A (mrad) it adds 1e-3 r^2 (k_Re + i k_Im) (N/mm) to the modal dynamic
stiffness, with k in N mm/mrad (M = k psi, psi in mrad, and the modal force of a moment M is
1e-3 r M since a rotation psi (mrad) is 1e-3 r A rad per mm of tip motion):

    D(omega, A) = k_b (1 - (omega/omega0)^2 + i eta) + 1e-3 r^2 (k_Re(r A) + i k_Im(r A))

and the first-harmonic steady state is |D(omega, A)| A = F (the amplitude-layered solution: each
amplitude A is a linear problem). For each A the equation is quadratic in omega^2 (`frf`); at the
peak Re D = 0, so A (eta k_b + 1e-3 r^2 k_Im(r A)) = F (`peak_response`).

The damper enters only through a pure-JAX, differentiable `k_of_psi(psi_a_mrad) -> (k_re, k_im)`
built by `damper_stiffness(shape, mu, contacts, load, method=...)`: "exact" (default) takes the
steady travel-limited cycle at each amplitude (`jaxdamp.amplitude`, from a gross-slip history
unless initial="assembly"); "interpolated" is the paper's, `complex_stiffness(method=
"interpolated")` on the Base-Cycle (exact for psi_a >= psi_BC, linear in the microslip range).

Units: A and tip displacements in mm, F in N, k_b in N/mm, f in Hz, r in mrad/mm, psi in mrad,
k in N mm/mrad.

The package: `scene` (the blade mode and the checked scene), `stiffness` (the damper as a complex
spring), `frf` (closed-form FRFs), `peaks` (the peak response and its compiled programs),
`peak_band` (the band of peaks over contact histories), `diagram` (the designer's diagram),
`modes` (a bladed disk's mode family from modal data, reduced per engine order to this one-mode
blade and the damper's platform path), `row` (the peaks across a blade row, per engine order),
`row_gradient` (their derivatives by the implicit function theorem at the roots found), `row_band`
(their band over contact histories), `row_diagram` (the row's worst peak against the force and
the damper's mass).
"""

from .scene import BladeMode as BladeMode
from .scene import Scene as Scene
from .scene import prepare_scene as prepare_scene
from .scene import validate_mode as validate_mode
from .stiffness import DamperStiffness as DamperStiffness
from .stiffness import STIFFNESS_METHODS as STIFFNESS_METHODS
from .stiffness import damper_stiffness as damper_stiffness
from .stiffness import damper_stiffness_kernel as damper_stiffness_kernel
from .stiffness import no_damper as no_damper
from .stiffness import register_stiffness_method as register_stiffness_method
from .stiffness import scaled_stiffness as scaled_stiffness
from .stiffness import stuck_damper as stuck_damper
from .stiffness import tabulated_stiffness as tabulated_stiffness
from .frf import FRF as FRF
from .frf import frf as frf
from .frf import frf_amplitude_grid as frf_amplitude_grid
from .frf import linear_frf as linear_frf
from .frf import response_amplitude_linear as response_amplitude_linear
from .peaks import Peaks as Peaks
from .peaks import ResponseCurves as ResponseCurves
from .peaks import curves_program as curves_program
from .peaks import design_peaks as design_peaks
from .peaks import peak_frequency_hz as peak_frequency_hz
from .peaks import peak_program as peak_program
from .peaks import peak_residual as peak_residual
from .peaks import peak_response as peak_response
from .peaks import response_curves as response_curves
from .peaks import path_peaks as path_peaks
from .peaks import series_peaks as series_peaks
from .peaks import path_curves_program as path_curves_program
from .peaks import path_response_curves as path_response_curves
from .peak_band import peak_band as peak_band
from .peak_band import peak_band_unchecked as peak_band_unchecked
from .diagram import DIAGRAM_MUS as DIAGRAM_MUS
from .diagram import DesignerDiagram as DesignerDiagram
from .diagram import designer_diagram as designer_diagram
from .diagram import diagram_program as diagram_program
from .stiffness import path_damper as path_damper
from .stiffness import path_cycle_kernel as path_cycle_kernel
from .modes import ModalFamily as ModalFamily
from .modes import NodalScene as NodalScene
from .modes import validate_family as validate_family
from .modes import nodal_scene as nodal_scene
from .modes import excited_nodal_diameter as excited_nodal_diameter
from .modes import family_from_blade_mode as family_from_blade_mode
from .row import RowResponse as RowResponse
from .row import row_response as row_response
from .row import row_program as row_program
from .row import engine_orders_of as engine_orders_of
from .row_gradient import RowGradient as RowGradient
from .row_gradient import row_gradient as row_gradient
from .row_gradient import peak_amplitudes_at as peak_amplitudes_at
from .row_band import RowBand as RowBand
from .row_band import row_band as row_band
from .row_band import row_band_program as row_band_program
from .row_diagram import RowDiagram as RowDiagram
from .row_diagram import row_diagram as row_diagram

__all__ = ["BladeMode", "Scene", "DamperStiffness", "FRF", "Peaks", "DesignerDiagram", "STIFFNESS_METHODS",
           "damper_stiffness", "register_stiffness_method", "scaled_stiffness", "stuck_damper",
           "no_damper", "frf", "frf_amplitude_grid", "response_amplitude_linear", "peak_residual",
           "peak_frequency_hz",
           "peak_response", "design_peaks", "designer_diagram", "validate_mode", "DIAGRAM_MUS",
           "damper_stiffness_kernel", "linear_frf", "ResponseCurves", "curves_program",
           "response_curves", "diagram_program", "peak_program", "prepare_scene", "peak_band", "peak_band_unchecked",
           "tabulated_stiffness", "path_damper", "path_cycle_kernel", "ModalFamily", "NodalScene",
           "validate_family",
           "nodal_scene", "excited_nodal_diameter", "family_from_blade_mode", "RowResponse",
           "row_response", "row_program", "engine_orders_of", "RowGradient", "row_gradient", "peak_amplitudes_at", "RowBand", "row_band", "row_band_program", "RowDiagram",
           "row_diagram", "path_peaks", "series_peaks", "path_curves_program",
           "path_response_curves"]
