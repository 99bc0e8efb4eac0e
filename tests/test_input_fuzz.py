"""A fuzz of the public API's input boundary (issue 58): the public entry points of jaxdamp and
jaxdamp_optimize below (57 functions, 241 parameters, 2212 pairs of a parameter and a bad value;
the building blocks documented as unchecked and traceable check what they get concretely, so
they are here too), each called with one input replaced by a generated bad one (wrong shape,
mismatched axes, NaN, +-inf, zero, negative, out of range, None, wrong type, a swapped argument,
the wrong damper model), must end in one of two ways:

- an exception raised by the library's own checks (ValueError or TypeError whose innermost frame
  is in jaxdamp's or jaxdamp_optimize's source, not in JAX or numpy) whose one-line message names
  the parameter, or
- a result whose status is not ok, or a SmallRotationWarning (a number outside the model's
  validity that says so).

A number marked ok, NaN marked ok, or a traceback from inside JAX or numpy fails. The checks run
before anything is traced, so the cases compile nothing (the few valid objects some calls need, a
Base-Cycle and a damper curve, are built once). Hypothesis draws the cases with a fixed seed
(derandomize): CI sees the same few hundred every run; HYPOTHESIS_SEED-free local runs may set
JAXDAMP_FUZZ_EXAMPLES to draw more.
"""

from __future__ import annotations

import functools
import math
import os
import traceback
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import jaxdamp as jd
import jaxdamp_optimize as jo
from jaxdamp.fit.loops import LoopError

NAN, INF = math.nan, math.inf
S60 = jd.family_shape("60sym")
WEDGE = jd.DamperShape(60.0, 60.0, 0.14, 0.8, br2_over_hr=0.8)
OWN_SOURCE = (str(Path(jd.__file__).resolve().parent), str(Path(jo.__file__).resolve().parent))
EXAMPLES = int(os.environ.get("JAXDAMP_FUZZ_EXAMPLES", "300"))


class Opaque:
    """Something that is no number, array, shape or option."""

    def __repr__(self):
        return "Opaque()"


# Bad values by the kind of input they replace. Each is invalid for every parameter of its kind.
BAD = {
    "mu": [None, NAN, INF, -INF, 0.0, -0.3, 7.0, "0.5", [0.3, 0.4, 0.5, 0.6], np.full((2, 2), 0.5),
           Opaque(), S60, True],
    "shape": [None, 0.5, "60sym", jd.DamperShape(95.0, 60.0, 0.14), jd.DamperShape(NAN, 60.0, 0.14),
              jd.DamperShape(60.0, 60.0, 0.9), jd.DamperShape(60.0, 60.0, 0.14, 0.0),
              jd.DamperShape(60.0, 60.0, 0.14, 1.5), jd.DamperShape(np.full(4, 60.0), 60.0, 0.14),
              jd.DamperShape(60.0, None, 0.14), jd.DamperShape(60.0, -INF, 0.14), jd.Contacts(),
              Opaque()],
    "wedge": [WEDGE, jd.DamperShape(60.0, 60.0, 0.14, 0.8, br2_over_hr=5.0)],
    "contacts": [jd.Contacts(kn=None), jd.Contacts(kt=None), jd.Contacts(-1.0), jd.Contacts(NAN),
                 jd.Contacts(INF), jd.Contacts(kt=0.0), jd.Contacts(np.full(5, 2e4)),
                 jd.Contacts(np.full((2, 3), 2e4)), jd.Contacts("a"), 0.5, jd.LoadCase(), Opaque()],
    "contacts_batch": [jd.Contacts(kn=None), jd.Contacts(-1.0), jd.Contacts(NAN), jd.Contacts(INF),
                       jd.Contacts(kt=0.0), jd.Contacts(np.full((2, 2), 2e4)), jd.Contacts("a"),
                       0.5, jd.LoadCase(), Opaque()],
    "load_batch": [jd.LoadCase(F_D=-1.0), jd.LoadCase(F_D=NAN), jd.LoadCase(q_star=0.0),
                   jd.LoadCase(q_star=None), jd.LoadCase(r_sin_beta=INF), jd.Contacts(), 3.0,
                   Opaque()],
    "load": [jd.LoadCase(F_D=-1.0), jd.LoadCase(F_D=NAN), jd.LoadCase(F_D=0.0), jd.LoadCase(q_star=0.0),
             jd.LoadCase(q_star=None), jd.LoadCase(F_D=np.full(4, 1000.0)),
             jd.LoadCase(r_sin_beta=INF), jd.Contacts(), 3.0, Opaque()],
    "mu_list": [None, NAN, [0.0], [-0.3], [7.0, 0.5], "0.5", np.full((2, 2), 0.5), Opaque(), [],
                S60],
    "psi": [None, NAN, INF, 0.0, -1.0, "2", Opaque(), [[1.0]], -INF],
    "psi0": [None, NAN, INF, -1.0, "2", Opaque(), [[1.0]], -INF],
    "psi_array": [None, NAN, [], [-1.0, 2.0], "2", [1.0, NAN], Opaque()],
    "shapes": [None, 0.5, "60sym", jd.DamperShape(95.0, 60.0, 0.14), jd.DamperShape(NAN, 60.0, 0.14),
               jd.DamperShape(60.0, 60.0, 0.9), jd.DamperShape(60.0, None, 0.14), jd.Contacts(),
               jd.DamperShape(np.full(4, 60.0), np.full(5, 60.0), 0.14), Opaque()],
    "force": [None, NAN, -1.0, 0.0, INF, "1", [[1.0]], [], [-5.0, 0.0], Opaque()],
    "mode": [jd.BladeMode(f0_hz=-1.0), jd.BladeMode(eta=2.0), jd.BladeMode(k_b=NAN),
             jd.BladeMode(r=0.0), jd.BladeMode(f0_hz=INF), 3.0, jd.Contacts(), "mode"],
    "motion": [3.0, "in_phase", Opaque(), jd.Contacts()],
    "count1": [-1, 0, 2.5, "3", None, True, NAN],
    "count0": [-1, 2.5, "3", None, True, NAN],
    "angles": [None, NAN, [95.0, 60.0], [-10.0, 60.0], "60", Opaque(), [60.0, INF]],
    "option": ["bogus", None, 3, Opaque()],
    "family_name": ["bogus", None, 3, Opaque(), "60SYM "],
    "order_text": ["bogus", None, Opaque(), "1.5", "-1", "", "3:1"],
    "direction": [None, NAN, [], [-1.0, 2.0], "2", [1.0, NAN, 0.0], Opaque(), [0.0, 0.0, 0.0]],
    "engine_orders": [[1.5], "all", None, [-1], [], [[1, 2]], [NAN]],
    "batch": [None, S60, 0.5, Opaque(), [S60, S60]],
    "designs_bad_leaf": ["lengths", "mu_nan", "theta_95", "kn_negative", "kn_per_pad_short",
                         "kn_none", "mu_2d", "wedge"],
}

# The words a message may use to name a parameter of each kind (besides the parameter's name).
ALIASES = {
    "shape": ("shape", "theta_l", "theta_r", "br_over_hr", "bl2_over_hl", "x_d"),
    "wedge": ("br2_over_hr", "wedge"),
    "contacts": ("contacts", "kn", "kt"),
    "contacts_batch": ("contacts", "kn", "kt"),
    "load_batch": ("load", "F_D", "q_star", "r_sin_beta"),
    "load": ("load", "F_D", "q_star", "r_sin_beta"),
    "mode": ("mode", "f0_hz", "eta", "k_b", "r "),
    "batch": ("designs", "batch"),
    "designs_bad_leaf": ("designs", "theta_l", "mu", "kn", "br2_over_hr", "batch"),
    "mu": ("mu",),
    "family_name": ("shape",),
    "order_text": ("engine_order",),
    "direction": ("motion",),
    "motion": ("motion", "modes", "family"),
    "angles": ("theta_l", "theta_r"),
    "mu_list": ("mu",),
    "option": ("objective",),
    "shapes": ("shape", "theta_l", "theta_r", "br_over_hr", "bl2_over_hl", "x_d"),
}


def _designs(case: str):
    """A batched Design with one bad leaf (the batch checks of issue 58, item 2)."""
    n = 4
    good = jd.stack_designs([S60] * n, mu=[0.3, 0.4, 0.5, 0.6])
    shape, mu, contacts, load = good
    if case == "lengths":
        return good._replace(shape=shape._replace(theta_r=np.full(n + 1, 60.0)))
    if case == "mu_nan":
        return good._replace(mu=np.array([0.3, NAN, 0.5, 0.6]))
    if case == "theta_95":
        return good._replace(shape=shape._replace(theta_l=np.full(n, 95.0)))
    if case == "kn_negative":
        return good._replace(contacts=contacts._replace(kn=-contacts.kn))
    if case == "kn_per_pad_short":
        return good._replace(contacts=jd.Contacts(np.full(3, 2e4), contacts.kt))
    if case == "kn_none":
        return good._replace(contacts=jd.Contacts(None, contacts.kt))
    if case == "mu_2d":
        return good._replace(mu=np.full((n, 2), 0.5))
    if case == "wedge":
        return good._replace(shape=shape._replace(br2_over_hr=np.full(n, 0.8)))
    raise AssertionError(case)


@functools.cache
def _base_cycle():
    return jd.base_cycle(S60, 0.5)


@functools.cache
def _damper():
    return jd.damper_stiffness(S60, 0.5)


@functools.cache
def _family():
    from jaxdamp.modal_file import EXAMPLE_PATH, load_modal_family

    return load_modal_family(EXAMPLE_PATH)


def _loop():
    """A measured-looking moment loop (two periods of an ellipse, positive energy)."""
    t = np.linspace(0.0, 4.0 * np.pi, 400)
    return (3.0 * np.cos(t), 4e4 * np.cos(t) - 1e4 * np.sin(t))


def _jd(name):
    """A public function: jaxdamp's top level, its building blocks, or (the batched forms behind a
    top-level function: amplitude_bands, sequence_curves) the module that defines it."""
    import jaxdamp.band
    import jaxdamp.sequence

    for space in (jd, jd.blocks, jaxdamp.band, jaxdamp.sequence):
        if name in getattr(space, "__all__", ()):
            return getattr(space, name)
    raise AttributeError(name)


# name -> (function, the valid call's arguments (a function: some are built once), the kind of
# each parameter the fuzz replaces). Parameters left out take their defaults.
E = (lambda **kw: (lambda: kw))  # noqa: E731
# The blade row's valid call and its parameters (row_response and row_band share them).
ROW_CALL = (lambda: dict(shape=S60, mu=0.5, modes=_family(), engine_orders=[3],  # noqa: E731
                         force_n=[2.0], h_l_mm=10.0))
ROW_KINDS = {"shape": "shape", "mu": "mu", "contacts": "contacts", "load": "load",
             "engine_orders": "engine_orders", "force_n": "force", "h_l_mm": "psi",
             "modes": "motion"}
ENTRY_POINTS = {
    "base_cycle": (_jd("base_cycle"), E(shape=S60, mu=0.5),
                   {"shape": "shape", "mu": "mu", "contacts": "contacts", "load": "load",
                    "shape#": "wedge"}),
    "cycle_numbers": (_jd("cycle_numbers"), E(shape=S60, mu=0.5),
                      {"shape": "shape", "mu": "mu", "contacts": "contacts", "load": "load",
                       "shape#": "wedge"}),
    "full_slip_statics": (_jd("full_slip_statics"), E(shape=S60, mu=0.5),
                          {"shape": "shape", "mu": "mu", "shape#": "wedge"}),
    "design_br": (_jd("design_br"), E(shape=S60, mu_max=0.7), {"shape": "shape", "mu_max": "mu"}),
    "five_numbers_jacobian": (_jd("five_numbers_jacobian"), E(shape=S60, mu=0.5),
                              {"shape": "shape", "mu": "mu", "contacts": "contacts", "load": "load",
                               "mode": "option", "shape#": "wedge"}),
    "k_im_gradient_at": (_jd("k_im_gradient_at"), E(psi_a_mrad=2.0, shape=S60, mu=0.5),
                         {"psi_a_mrad": "psi0", "shape": "shape", "mu": "mu", "contacts": "contacts",
                          "load": "load"}),
    "amplitude_cycle": (_jd("amplitude_cycle"), E(shape=S60, mu=0.5, psi_a_mrad=2.0),
                        {"shape": "shape", "mu": "mu", "psi_a_mrad": "psi", "contacts": "contacts",
                         "load": "load", "initial": "option", "max_tracts": "count1",
                         "motion": "motion", "shape#": "wedge"}),
    "amplitude_curves": (_jd("amplitude_curves"), E(shapes=S60, mu=0.5, psi_a_mrad=[1.0, 2.0]),
                         {"shapes": "shapes", "mu": "mu_list", "psi_a_mrad": "psi_array",
                          "contacts": "contacts_batch", "load": "load_batch", "shapes#": "wedge"}),
    "amplitude_band": (_jd("amplitude_band"), E(shape=S60, mu=0.5, psi_a_mrad=2.0),
                       {"shape": "shape", "mu": "mu", "psi_a_mrad": "psi", "contacts": "contacts",
                        "load": "load", "n_samples": "count1", "shape#": "wedge"}),
    "elliptic_cycle": (_jd("elliptic_cycle"),
                       lambda: dict(shape=S60, mu=0.5, amplitude_mrad=2.0,
                                    motion=jd.interblade_motion(90.0, 20.0, h_l_mm=10.0)),
                       {"shape": "shape", "mu": "mu", "amplitude_mrad": "psi",
                        "motion": "motion", "contacts": "contacts", "load": "load"}),
    "path_base_cycle": (_jd("path_base_cycle"),
                        lambda: dict(shape=S60, mu=0.5, motion=jd.in_phase_motion(100.0)),
                        {"shape": "shape", "mu": "mu", "motion": "motion", "contacts": "contacts",
                         "load": "load"}),
    "interblade_sweep": (_jd("interblade_sweep"),
                         E(shape=S60, mu=0.5, amplitude_mrad=2.0, phis_deg=[0.0, 90.0],
                           h_c_mm=20.0, h_l_mm=10.0),
                         {"shape": "shape", "mu": "mu", "amplitude_mrad": "psi",
                          "contacts": "contacts", "load": "load"}),
    "complex_stiffness": (_jd("complex_stiffness"),
                          lambda: dict(bc=_base_cycle(), psi_a_mrad=[2.0]),
                          {"psi_a_mrad": "psi_array", "method": "option", "initial": "option"}),
    "damper_stiffness": (_jd("damper_stiffness"), E(shape=S60, mu=0.5),
                         {"shape": "shape", "mu": "mu", "contacts": "contacts", "load": "load",
                          "method": "option", "shape#": "wedge"}),
    "design_peaks": (_jd("design_peaks"), E(shape=S60, mu=0.5, force_n=[2.0]),
                     {"shape": "shape", "mu": "mu", "contacts": "contacts", "load": "load",
                      "mode": "mode", "force_n": "force", "method": "option", "shape#": "wedge"}),
    "response_curves": (_jd("response_curves"), E(shape=S60, mu=0.5, force_n=[2.0]),
                        {"shape": "shape", "mu": "mu", "contacts": "contacts", "load": "load",
                         "mode": "mode", "force_n": "force", "shape#": "wedge"}),
    "path_response_curves": (_jd("path_response_curves"), E(shape=S60, mu=0.5, force_n=[2.0]),
                             {"shape": "shape", "mu": "mu", "contacts": "contacts",
                              "load": "load", "mode": "mode", "force_n": "force",
                              "motion": "motion", "initial": "option"}),
    "peak_response": (_jd("peak_response"),
                      lambda: dict(damper=_damper(), mode=jd.BladeMode(), force_n=[2.0]),
                      {"force_n": "force", "mode": "mode"}),
    "designer_diagram": (_jd("designer_diagram"), E(shape=S60),
                         {"shape": "shape", "mode": "mode", "contacts": "contacts", "load": "load",
                          "force_n": "force", "fd_n": "force", "mu": "mu_list", "shape#": "wedge"}),
    "evaluate_designs": (_jd("evaluate_designs"), E(designs=None),
                         {"designs": "batch", "designs%": "designs_bad_leaf"}),
    "base_cycles": (_jd("base_cycles"), E(shapes=None),
                    {"shapes": "batch", "shapes%": "designs_bad_leaf"}),
    "batch_jacobian": (_jd("batch_jacobian"), E(designs=None),
                       {"designs": "batch", "designs%": "designs_bad_leaf", "mode": "option"}),
    "stack_designs": (_jd("stack_designs"), E(shapes=[S60, S60], mu=[0.3, 0.5]),
                      {"shapes": "shape", "mu": "mu_list", "contacts": "contacts", "load": "load"}),
    "sweep": (_jd("sweep"), E(theta_l=[50.0, 60.0], theta_r=[60.0], mu=[0.5]),
              {"mu": "mu_list", "contacts": "contacts", "load": "load"}),
    "row_response": (_jd("row_response"), ROW_CALL, {**ROW_KINDS, "initial": "option"}),
    "peak_distribution": (_jd("peak_distribution"),
                          lambda: dict(shape=S60, scenarios=jd.sample_scenarios(
                              __import__("jax").random.PRNGKey(0), 4), force_n=2.0),
                          {"shape": "shape", "force_n": "force", "history": "option",
                           "mode": "mode"}),
    "sample_scenarios": (_jd("sample_scenarios"),
                         lambda: dict(key=__import__("jax").random.PRNGKey(0), n=4),
                         {"n": "count1", "contacts": "contacts", "load": "load"}),
    "fit_loops": (_jd("fit_loops"), lambda: dict(loops=[_loop()], shape=S60),
                  {"shape": "shape", "load": "load", "initial": "option", "mu": "option",
                   "max_steps": "count1", "rtol": "psi"}),
    "sample_loop": (_jd("sample_loop"), E(shape=S60, mu=0.5, psi_a_mrad=2.0,
                                          t=np.linspace(0.0, 2.0, 50)),
                    {"shape": "shape", "mu": "mu", "psi_a_mrad": "psi", "contacts": "contacts",
                     "load": "load"}),
    "in_phase_motion": (_jd("in_phase_motion"), E(q_star_mm=100.0), {"q_star_mm": "psi"}),
    "interblade_motion": (_jd("interblade_motion"), E(phi_deg=90.0, h_c_mm=20.0, h_l_mm=10.0),
                          {"q_star_mm": "psi", "h_l_mm": "psi"}),
    "full_slip_work_shape_factors": (_jd("full_slip_work_shape_factors"), E(shape=S60, mu=0.5),
                                     {"shape": "shape", "mu": "mu", "shape#": "wedge"}),
    "admissible_polytope": (_jd("admissible_polytope"), E(shape=S60, mu=0.5),
                            {"shape": "shape", "mu": "mu", "shape#": "wedge"}),
    "section_geometry": (_jd("section_geometry"), E(shape=S60), {"shape": "shapes"}),
    "amplitude_bands": (_jd("amplitude_bands"), E(shape=S60, mu=0.5, psi_a_mrad=[1.0, 2.0]),
                        {"shape": "shape", "mu": "mu", "psi_a_mrad": "psi_array",
                         "contacts": "contacts", "load": "load", "n_samples": "count1",
                         "shape#": "wedge"}),
    "sequence_curves": (_jd("sequence_curves"), E(shapes=S60, mu=0.5, psi_a_mrad=[1.0, 2.0]),
                        {"shapes": "shapes", "mu": "mu_list", "psi_a_mrad": "psi_array",
                         "contacts": "contacts_batch", "load": "load_batch", "shapes#": "wedge"}),
    "centred_br": (_jd("centred_br"), E(theta_l=[50.0, 60.0], theta_r=[60.0, 70.0]),
                   {"theta_l": "angles", "theta_r": "angles", "mu_max": "mu"}),
    "contact_energies": (_jd("contact_energies"), lambda: dict(bc=_base_cycle()),
                         {"psi_a_mrad": "psi0"}),
    "peak_band": (_jd("peak_band"), E(shape=S60, mu=0.5, force_n=[2.0]),
                  {"shape": "shape", "mu": "mu", "contacts": "contacts", "load": "load",
                   "mode": "mode", "force_n": "force", "n_samples": "count1", "shape#": "wedge"}),
    "row_band": (_jd("row_band"), ROW_CALL, {**ROW_KINDS, "n_samples": "count1"}),
    "nodal_scene": (_jd("nodal_scene"),
                    lambda: dict(family=_family(), engine_order=3, q_star_mm=100.0, h_l_mm=10.0),
                    {"engine_order": "count0", "q_star_mm": "psi", "h_l_mm": "psi",
                     "family": "motion"}),
    "prepare_scene": (_jd("prepare_scene"), E(shape=S60, mu=0.5),
                      {"shape": "shape", "mu": "mu", "contacts": "contacts", "load": "load",
                       "mode": "mode", "shape#": "wedge"}),
    "path_damper": (_jd("path_damper"),
                    lambda: dict(shape=S60, mu=0.5, contacts=jd.Contacts(), load=jd.LoadCase(),
                                 motion=jd.interblade_motion(90.0, 20.0, h_l_mm=10.0)),
                    {"shape": "shape", "mu": "mu", "contacts": "contacts", "load": "load",
                     "motion": "motion", "initial": "option"}),
    "frf": (_jd("frf"), lambda: dict(damper=_damper(), mode=jd.BladeMode(), force_n=2.0,
                                     amplitude_mm=[0.01, 0.02]),
            {"force_n": "force", "mode": "mode", "amplitude_mm": "psi_array"}),
    "linear_frf": (_jd("linear_frf"), E(mode=jd.BladeMode(), k_re=1e4, force_n=2.0),
                   {"force_n": "force", "mode": "mode", "n": "count1"}),
    "stuck_damper": (_jd("stuck_damper"), E(k_re_stuck=1e4), {"k_re_stuck": "psi0"}),
    "scaled_stiffness": (_jd("scaled_stiffness"),
                         lambda: dict(ref=_damper(), fd_ref_n=1000.0, fd_n=800.0),
                         {"fd_ref_n": "psi", "fd_n": "psi"}),
    "fit_problem": (_jd("fit_problem"), lambda: dict(loops=[_loop()], shape=S60),
                    {"shape": "shape", "load": "load", "initial": "option", "mu": "option"}),
    "validated_range_violations": (_jd("validated_range_violations"),
                                   E(contacts=jd.Contacts(), load=jd.LoadCase()),
                                   {"contacts": "contacts", "load": "load"}),
    "full_slip_state": (_jd("full_slip_state"),
                        E(shape=S60, mu=0.5, friction_signs=np.array([1.0, -1.0, -1.0])),
                        {"shape": "shape", "mu": "mu"}),
    "straight_motion": (_jd("straight_motion"), E(direction=[0.0, 0.1, 0.0]),
                        {"direction": "direction", "h_l_mm": "psi"}),
    "general_motion": (_jd("general_motion"), E(direction=[0.0, 0.1, 1.0], h_l_mm=10.0),
                       {"direction": "direction", "h_l_mm": "psi"}),
    "engine_orders_of": (_jd("engine_orders_of"), E(text="all", n_blades=24),
                         {"text": "order_text", "n_blades": "count1"}),
    "family_shape": (_jd("family_shape"), E(name="60sym"), {"name": "family_name"}),
    "k_im_at_amplitude": (jo.k_im_at_amplitude, E(shape=S60, mus=[0.5], psi_a_mrad=2.0),
                          {"shape": "shape", "mus": "mu_list", "psi_a_mrad": "psi",
                           "contacts": "contacts", "load": "load"}),
    "make_problem": (jo.make_problem, E(), {"mus": "mu_list", "kn": "psi", "kt": "psi", "load": "load"}),
    "parse_objective": (jo.parse_objective, E(), {"name": "option"}),
}

# Parameters whose None is valid: "the default" (an optional mode, motion (in-phase) or grid).
NONE_IS_DEFAULT = {
    ("amplitude_cycle", "motion"), ("path_response_curves", "motion"), ("design_peaks", "mode"),
    ("response_curves", "mode"), ("path_response_curves", "mode"), ("designer_diagram", "mode"),
    ("designer_diagram", "force_n"), ("designer_diagram", "fd_n"), ("peak_distribution", "mode"),
    ("contact_energies", "psi_a_mrad"), ("path_damper", "motion"), ("peak_band", "mode"),
    ("straight_motion", "h_l_mm"),
}
UNIT_SUFFIXES = ("_mm", "_mrad", "_n", "_deg", "_hz")


def _valid_batch():
    return jd.stack_designs([S60] * 4, mu=[0.3, 0.4, 0.5, 0.6])


CASES = sorted((name, param) for name, (_, _, kinds) in ENTRY_POINTS.items() for param in kinds)


def _call(name: str, param: str, bad):
    fn, base, kinds = ENTRY_POINTS[name]
    kwargs = dict(base())  # a copy: the valid call is shared by every case
    for key in ("designs", "shapes"):
        if key in kwargs and kwargs[key] is None:
            kwargs[key] = _valid_batch()
    kind = kinds[param]
    target = param.rstrip("#%")
    kwargs[target] = _designs(bad) if kind == "designs_bad_leaf" else bad
    return fn(**kwargs)


def _status_not_ok(out) -> bool:
    status = getattr(out, "status", None)
    if status is None and isinstance(out, tuple):
        for part in out:
            got = getattr(part, "status", None)
            status = got if got is not None else status
    if status is None:
        return False
    return bool(np.all(np.asarray(status) != jd.RESULTS.ok))


def _own_frame(exc: BaseException) -> bool:
    frames = traceback.extract_tb(exc.__traceback__)
    return bool(frames) and str(Path(frames[-1].filename).resolve()).startswith(OWN_SOURCE)


def _outcome(name: str, param: str, bad) -> str | None:
    """None when the call ends as the module docstring says, else what went wrong."""
    kind = ENTRY_POINTS[name][2][param]
    target = param.rstrip("#%")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            out = _call(name, param, bad)
        except (ValueError, TypeError, LoopError) as e:
            msg = str(e)
            if not _own_frame(e):
                return f"raised from outside jaxdamp: {type(e).__name__}: {msg[:200]}"
            stem = next((target[: -len(u)] for u in UNIT_SUFFIXES if target.endswith(u)), target)
            names = (target, stem) + ALIASES.get(kind, ())
            if not any(n in msg for n in names):
                return f"message names none of {names}: {msg[:200]}"
            if "\n" in msg.strip():
                return f"message of more than one line: {msg[:200]}"
            return None
        except Exception as e:  # noqa: BLE001 - any other exception is a failure of the boundary
            return f"{type(e).__name__} (not the library's check): {str(e)[:200]}"
    if any(issubclass(w.category, jd.SmallRotationWarning) for w in caught):
        return None
    if _status_not_ok(out):
        return None
    return f"returned a result marked ok: {type(out).__name__}"


@settings(max_examples=EXAMPLES, deadline=None, derandomize=True, database=None,
          suppress_health_check=list(HealthCheck))
@given(st.data())
def test_bad_inputs_are_refused_in_one_line_or_carry_a_status(data):
    name, param = data.draw(st.sampled_from(CASES), label="entry point, parameter")
    kind = ENTRY_POINTS[name][2][param]
    bad = data.draw(st.sampled_from(BAD[kind]), label="bad value")
    if bad is None and (name, param.rstrip("#%")) in NONE_IS_DEFAULT:
        return
    problem = _outcome(name, param, bad)
    assert problem is None, f"{name}({param.rstrip('#%')}={bad!r}): {problem}"


# The examples of issue 58, each as the user wrote it: one line naming the parameter, or a status.
ISSUE_EXAMPLES = {
    "a wedge to cycle_numbers": lambda: jd.cycle_numbers(WEDGE, 0.5),
    "br2_over_hr=5": lambda: jd.cycle_numbers(jd.DamperShape(60, 60, 0.14, 0.8, br2_over_hr=5), 0.5),
    "negative forces to peak_response": lambda: jd.peak_response(_damper(), jd.BladeMode(),
                                                                 [-5.0, 0.0]),
    "negative force to designer_diagram": lambda: jd.designer_diagram(S60, force_n=[-1.0]),
    "NaN F_D to designer_diagram": lambda: jd.designer_diagram(S60, fd_n=[NAN]),
    "eta 0 to designer_diagram": lambda: jd.designer_diagram(S60, jd.BladeMode(eta=0.0)),
    "Contacts(kn=None)": lambda: jd.base_cycle(S60, 0.5, jd.Contacts(kn=None)),
    "a batched Design to base_cycle": lambda: jd.base_cycle(_valid_batch()),
    "a list of mu to amplitude_cycle": lambda: jd.amplitude_cycle(S60, [0.3, 0.4, 0.5, 0.6], 2.0),
    "a list of mu to design_peaks": lambda: jd.design_peaks(S60, [0.3, 0.4, 0.5, 0.6]),
    "a list of mu to five_numbers_jacobian": lambda: jd.five_numbers_jacobian(S60, [0.3, 0.4, 0.5,
                                                                                  0.6]),
    "q* of the load against the motion's": lambda: jd.amplitude_cycle(
        S60, 0.5, 2.0, load=jd.LoadCase(q_star=50.0), motion=jd.in_phase_motion(100.0)),
    "engine order 1.5": lambda: jd.row_response(S60, 0.5, modes=_family(), engine_orders=[1.5],
                                                h_l_mm=10.0),
    "engine orders 'all'": lambda: jd.row_response(S60, 0.5, modes=_family(), engine_orders="all",
                                                   h_l_mm=10.0),
    "modal force 0": lambda: jd.row_response(
        S60, 0.5, modes=_family()._replace(modal_force=np.zeros_like(_family().modal_force)),
        engine_orders=[3], h_l_mm=10.0),
    "rtol -1 to fit_loops": lambda: jd.fit_loops([_loop()], S60, rtol=-1.0),
    "a loop of negative energy to fit_loops": lambda: jd.fit_loops(
        [(_loop()[0], -_loop()[1])], S60),
    "mismatched batch axes": lambda: jd.evaluate_designs(_designs("lengths")),
    "NaN mu in a batch": lambda: jd.evaluate_designs(_designs("mu_nan")),
    "theta_l 95 in a batch": lambda: jd.evaluate_designs(_designs("theta_95")),
    "negative kn in a batch": lambda: jd.evaluate_designs(_designs("kn_negative")),
    "scalar contacts, batched shape": lambda: jd.evaluate_designs(jd.Design(
        jd.DamperShape(np.full(4, 60.0), np.full(4, 60.0), 0.14), np.full(4, 0.5),
        jd.Contacts(np.full(3, 2e4), 3e3))),
}


@pytest.mark.parametrize("example", sorted(ISSUE_EXAMPLES))
def test_the_issue_examples_get_one_line(example):
    with pytest.raises((ValueError, TypeError)) as info:
        ISSUE_EXAMPLES[example]()
    assert _own_frame(info.value), info.value
    assert "\n" not in str(info.value).strip()


def test_complex_stiffness_beyond_the_small_rotation_limit_says_so():
    with pytest.warns(jd.SmallRotationWarning, match="psi_a"):
        jd.complex_stiffness(_base_cycle(), [1e6], method="interpolated")


@pytest.mark.slow  # 13.5 worker-s (run of 2026-11-28)
def test_a_batch_of_three_is_three_designs_not_three_pads():
    """stack_designs' (n,) stiffness is one per design at n = 3 as at n = 4 (it was read as per
    pad at 3 and refused at 4): the batch's values equal the designs' one by one."""
    kn = [1.5e4, 2e4, 2.5e4]
    batch = jd.stack_designs([S60] * 3, [0.4, 0.5, 0.6], [jd.Contacts(k, 3e3) for k in kn])
    jac, (values, status) = jd.batch_jacobian(batch)
    assert np.asarray(jac.k_re_fs.contacts.kn).shape == (3,)
    for i, (k, m) in enumerate(zip(kn, [0.4, 0.5, 0.6])):
        one = jd.five_numbers_jacobian(S60, m, jd.Contacts(k, 3e3))
        assert float(values.k_re_fs[i]) == pytest.approx(float(one.values.k_re_fs), rel=1e-12)
        assert float(jac.k_re_fs.contacts.kn[i]) == pytest.approx(float(one.d.k_re_fs.contacts.kn),
                                                                  rel=1e-9)
