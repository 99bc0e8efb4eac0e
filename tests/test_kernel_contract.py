"""The kernel contract (issue 62): every exported `*_kernel` is the unchecked, traceable form of
its entry point. A walk over every public module's `__all__` traces each one under
`jax.eval_shape` and under `jax.vmap` over two designs (no compile, no host loop, no float() of a
tracer). Host-driven forms are named `*_unchecked` instead; a kernel added without a case here
fails the walk."""

import importlib
import pkgutil

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd

jd.enable_x64()

SHAPE = jd.family_shape("60sym")


def _design(mu=0.5):
    return tuple(jd.Design(SHAPE, mu).prepared())


def _two(tree_a, tree_b):
    """Two concrete pytrees stacked on a leading axis (a batch of two)."""
    return jax.tree.map(lambda a, b: jnp.stack([jnp.asarray(a), jnp.asarray(b)]), tree_a, tree_b)


Q_STAR = float(jd.LoadCase().q_star)


def _straight():
    return jd.interblade_motion(180.0, 10.0, Q_STAR, 30.0)


def _ellipse():
    return jd.interblade_motion(90.0, 10.0, Q_STAR, 30.0)


def _mode():
    return jd.BladeMode()


def _scenario():
    from jaxdamp.uncertainty import Scenarios

    s = jd.sample_scenarios(jax.random.PRNGKey(0), 2)
    assert isinstance(s, Scenarios)
    return jax.tree.map(lambda v: v[0], s)


# name -> (function of a design tuple (shape, mu, contacts, load) that calls the kernel). Each
# runs under eval_shape on one design, and under vmap over two designs (mu 0.4, 0.5).
CASES = {
    "statics_kernel": lambda d: jd.statics_kernel(d[0], d[1]),
    "full_slip_work_shape_factors_kernel": lambda d: _module("statics").full_slip_work_shape_factors_kernel(d[0], d[1]),
    "design_br_kernel": lambda d: _module("statics").design_br_kernel(d[0], d[1], -0.45, 0.45),
    "base_cycle_kernel": lambda d: jd.base_cycle_kernel(*d),
    "five_numbers_kernel": lambda d: jd.five_numbers_kernel(jd.base_cycle_kernel(*d)),
    "summary_kernel": lambda d: _module("batch").summary_kernel(jd.Design(*d)),
    "amplitude_kernel": lambda d: jd.amplitude_kernel(*d, 2.0),
    "probe_kernel": lambda d: _module("sequence").probe_kernel(*d, 2.0),
    "curves_kernel": lambda d: jd.curves_kernel(*d, jnp.array([1.0, 2.0])),
    "band_kernel": lambda d: _module("band").band_kernel(*d, 2.0, jax.random.PRNGKey(0),
                                                         n_samples=8, steps=1),
    "elliptic_kernel": lambda d: jd.elliptic_kernel(*d, 2.0, _ellipse()),
    "gross_slip_amplitude_kernel": lambda d: _module("ellipse").gross_slip_amplitude_kernel(*d, _straight()),
    "path_base_cycle_kernel": lambda d: jd.path_base_cycle_kernel(*d, _straight()),
    "path_cycle_kernel": lambda d: jd.path_cycle_kernel(*d, 2.0, _ellipse()),
    "path_cycle_kernel (in phase)": lambda d: jd.path_cycle_kernel(*d, 2.0, None, "gross_slip"),
    "platform_force_kernel": lambda d: _module("platform_force").platform_force_kernel(
        jd.amplitude_kernel(*d, 2.0), 30.0),
    # its result holds k(psi) as a function: traced through it
    "damper_stiffness_kernel": lambda d: _stiffness_at(jd.damper_stiffness_kernel(*d, "interpolated")),
    "magnification_kernel": lambda d: jd.magnification_kernel(d[0], _scenario(), d[3], _mode(),
                                                              jnp.array([5.0])),
    "refit_kernel": lambda d: _module("sequence").refit_kernel(_CURVE, *d),
    "hbm_aft_kernel": lambda d: _baselines().hbm_aft_kernel(*d, 2.0, 32),
    "regularized_aft_kernel": lambda d: _baselines().regularized_aft_kernel(*d, 2.0, 1e-4, 32),
    "time_march_kernel": lambda d: _baselines().time_march_kernel(*d, 1e-3, 8, max_pairs=1),
    "hbm_aft_path_kernel": lambda d: _baselines().hbm_aft_path_kernel(*d, 2.0, _ellipse(), 32, 2,
                                                                       n_load=2),
}
_CURVE = None  # refit_kernel's curve: one concrete StiffnessCurve, built once (below)


def _stiffness_at(damper):
    return damper.k_of_psi(jnp.array([0.5, 2.0])), damper.status


def _module(name):
    return importlib.import_module(f"jaxdamp.{name}")


def _baselines():
    return importlib.import_module("jaxdamp.baselines")


def exported_kernels() -> dict:
    """name -> function of every `*_kernel` in a public module's __all__ (the library's core,
    response, fit and baselines; the CLI, plotting and paper layers export none)."""
    found = {}
    for info in pkgutil.walk_packages(jd.__path__, "jaxdamp."):
        if any(part in info.name for part in (".cli", ".plotting", ".paper")):
            continue
        module = importlib.import_module(info.name)
        for name in getattr(module, "__all__", []):
            if name.endswith("_kernel"):
                found.setdefault(name, getattr(module, name))
    return found


def test_every_exported_kernel_has_a_case():
    missing = sorted(set(exported_kernels()) - {name.split(" ")[0] for name in CASES})
    assert not missing, f"exported kernels without a traced case here: {missing}"


@pytest.mark.parametrize("name", sorted(CASES))
def test_kernel_traces_under_eval_shape_and_vmap(name):
    """Under eval_shape, and under vmap over two designs with every leaf gaining the batch axis;
    a kernel returns a pytree of arrays (a result type, never a bare tuple)."""
    global _CURVE
    if name == "refit_kernel" and _CURVE is None:
        from jaxdamp.curves import broadcast_designs

        shape = jax.tree.map(lambda v: np.array([v]), SHAPE)
        designs = broadcast_designs((shape, np.array([0.5]), jd.Contacts(), jd.LoadCase()), 1, np)
        _CURVE = jax.tree.map(lambda v: v[0], jd.stiffness_curve(designs, 0.5, 5.0))
    call = CASES[name]
    one = jax.eval_shape(call, _design())
    assert jax.tree.leaves(one), name
    if name.endswith("_kernel") and name != "damper_stiffness_kernel":  # (traced through its k)
        assert type(one) is not tuple, f"{name} returns a bare tuple"
    batched = jax.eval_shape(jax.vmap(call), _two(_design(0.4), _design(0.5)))
    for a, b in zip(jax.tree.leaves(one), jax.tree.leaves(batched)):
        assert b.shape == (2, *a.shape), (name, a.shape, b.shape)
