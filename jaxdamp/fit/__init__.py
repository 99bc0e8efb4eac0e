"""Contact parameters (mu, kn, kt) from measured hysteresis loops, with their uncertainty.

Two kinds of loop, freely mixed: moment loops (psi in mrad, M in N mm; below) and per-contact loops
(one contact's relative displacement d in mm against its tangential or normal force in N, recorded
at a given platform amplitude psi_a; `analyse_contact_loop`). A per-contact loop is compared as the
force against its own displacement on each half: the measured d's turning points mark the
reversals, a sample on a stretch where d decreases is compared with the model half along which the
contact's d decreases, at the same d (the model loop centred on the measured centre), minus a force
offset. The model's d is d_t = T / kt - slip (tangential; T = -kt (gt - slip), so gt = -d_t + const)
or d_n = N / kn (normal), exact and piecewise linear over the steady cycle from `amplitude_kernel`;
forces are in units of F_D in the model and N in the data (times load.F_D).

A measured loop is a series of samples (psi_i in mrad, M_i in N mm), several periods long, sampled
anyhow, with noise and a constant offset in each channel. `analyse_loop` finds its turning points,
its centre psi_c and amplitude psi_a (medians of the per-period extremes), and gives every sample
its *travel phase*: the half it lies on (forward = psi decreasing, the half that starts at the
Base-Cycle's state 0, as in `amplitude.py`) and the fraction u in [0, 1] of that half's travel.

The residual of a sample is the measured moment minus the model's exact steady loop
(`amplitude_kernel` at the measured psi_a, from the chosen history) at the same half and travel
fraction, minus a per-loop moment offset: the loops are compared as functions of the travel phase,
never point to nearest point, so the corners (where a contact starts to slip) count with their
full weight. The psi offset is the measured centre psi_c.

Parameters theta (the solver's unknowns): log mu (one shared, or one per contact), log(kn / K_REF)
and log(kt / K_REF) (shared, per side: R1 | L1 = L2, or per contact), and one moment offset per loop
in units of the data's moment scale. Logs keep mu, kn and kt positive and the problem well scaled.

The solve is optimistix's Levenberg-Marquardt (its QR linear solve; the Jacobian one matrix per
point, by forward mode through the exact cycle's while loops: a custom JVP of the residuals). Two stages: plain least squares from a generic start, then a
robust pseudo-Huber loss (residuals rescaled, r * sqrt(2 / (1 + sqrt(1 + (r/delta)^2))), so that
sum of squares = 2 delta^2 sum (sqrt(1 + (r/delta)^2) - 1)) with delta = ROBUST_DELTA times the
residuals' robust standard deviation (1.4826 MAD) after stage one. Outliers then weigh like
|r| instead of r^2.

Uncertainty: the Gauss-Newton covariance s^2 (J^T J)^-1 of the rescaled residuals at the optimum
(J from forward mode, s^2 = sum r^2 / (n - p)), standard errors, correlations, and confidence
intervals (for mu, kn, kt: exp of the log-parameter's interval, so they are asymmetric). A parameter
is reported as NOT IDENTIFIABLE (value null) when the Jacobian has a (near) null direction it takes
part in, or when its interval would span more than a factor MAX_SPAN; the intervals of the others
come from the pseudo-inverse of J^T J without the null directions (nothing held fixed).

The package: `loops` (measured loops, numpy), `model` (the model's loops, JAX), `solve` (the fit),
`result` (its result, uncertainty and identifiability), `synthetic` (model loops to test with).
"""


from .loops import COMPONENTS as COMPONENTS
from .loops import MIN_LOOP_AREA as MIN_LOOP_AREA
from .loops import ContactLoop as ContactLoop
from .loops import LoopError as LoopError
from .loops import MomentLoop as MomentLoop
from .loops import analyse_contact_loop as analyse_contact_loop
from .loops import analyse_loop as analyse_loop
from .loops import loop_direction_error as loop_direction_error
from .loops import loop_work as loop_work
from .model import contact_loop_force as contact_loop_force
from .model import contact_path as contact_path
from .model import loop_model_moment as loop_model_moment
from .solve import DEFAULT_START as DEFAULT_START
from .solve import GROUPINGS as GROUPINGS
from .solve import K_REF as K_REF
from .solve import ROBUST_DELTA as ROBUST_DELTA
from .solve import FitProblem as FitProblem
from .solve import FitSpec as FitSpec
from .solve import fit_loops as fit_loops
from .solve import fit_problem as fit_problem
from .solve import fit_residuals as fit_residuals
from .result import MAX_SPAN as MAX_SPAN
from .result import LoopFit as LoopFit
from .result import identify as identify
from .synthetic import sample_contact_loop as sample_contact_loop
from .synthetic import sample_loop as sample_loop

__all__ = ["MomentLoop", "ContactLoop", "analyse_contact_loop", "loop_work", "loop_direction_error",
           "MIN_LOOP_AREA", "contact_path", "contact_loop_force",
           "sample_contact_loop", "COMPONENTS", "LoopFit", "FitSpec", "LoopError", "analyse_loop", "fit_loops",
           "loop_model_moment", "sample_loop", "identify", "FitProblem", "fit_problem",
           "fit_residuals", "DEFAULT_START", "GROUPINGS", "K_REF", "MAX_SPAN", "ROBUST_DELTA"]
