"""The paper's study: its reference tables and shape family, the comparison of the 60sym family
(five numbers, Table 11 scores, qualitative findings, report) and the calibration of the contact
stiffness against Tables B3.1/B4.1. Built on the core's public API; the whole study with its
figures is `jaxdamp.plotting.run_study` (it draws, so it lives one layer up)."""

from ..geometry import FAMILY as FAMILY
from ..geometry import family_shape as family_shape
from ..geometry import paper_tables as paper_tables
from .calibration import CalibrationResult as CalibrationResult
from .calibration import CalibrationTargets as CalibrationTargets
from .calibration import calibrate as calibrate
from .calibration import comparison_table as comparison_table
from .calibration import paper_targets as paper_targets
from .study import compute_study as compute_study
from .study import write_study as write_study


__all__ = ["FAMILY", "family_shape", "paper_tables", "CalibrationResult", "CalibrationTargets",
           "calibrate", "comparison_table", "paper_targets", "compute_study", "write_study"]
