"""The paper's study: its reference tables and shape family, the comparison of the 60sym family
(five numbers, Table 11 scores, qualitative findings, report) and the calibration of the contact
stiffness against Tables B3.1/B4.1. Built on the core's public API."""

from ..geometry import FAMILY as FAMILY
from ..geometry import family_shape as family_shape
from ..geometry import paper_tables as paper_tables
from .calibration import CalibrationResult as CalibrationResult
from .calibration import CalibrationTargets as CalibrationTargets
from .calibration import calibrate as calibrate
from .calibration import comparison_table as comparison_table
from .calibration import paper_targets as paper_targets
from .study import run_study as run_study
