"""Figures (matplotlib); every function returns its Figure. Importing this package chooses no
backend: the CLI picks Agg before it plots, notebooks keep their inline backend."""

from .figures import default_amplitudes as default_amplitudes
from .figures import force_track as force_track
from .style import mu_color as mu_color
from .figures import plot_complex_stiffness as plot_complex_stiffness
from .figures import plot_energy as plot_energy
from .figures import plot_equilibrium_tracks as plot_equilibrium_tracks
from .figures import plot_family_comparison as plot_family_comparison
from .figures import plot_moment_cycles as plot_moment_cycles
from .section import plot_section as plot_section
from .figures import plot_stretched_cycles as plot_stretched_cycles
from .section import section_lines_of_action as section_lines_of_action
from .sweep import heatmap_figure as heatmap_figure
from .sweep import write_sweep as write_sweep
from .study import key_figure as key_figure
from .study import run_study as run_study
from .study import study_figures as study_figures
from .amplitude import amplitude_stiffness_data as amplitude_stiffness_data
from .amplitude import plot_amplitude_stiffness as plot_amplitude_stiffness
from .motions import plot_ibpa_claim as plot_ibpa_claim


__all__ = ["default_amplitudes", "force_track", "mu_color", "plot_complex_stiffness",
           "plot_energy", "plot_equilibrium_tracks", "plot_family_comparison",
           "plot_moment_cycles", "plot_section", "plot_stretched_cycles",
           "section_lines_of_action", "heatmap_figure", "write_sweep", "key_figure", "run_study",
           "study_figures", "amplitude_stiffness_data", "plot_amplitude_stiffness",
           "plot_ibpa_claim"]
