"""jaxdamp.cli.exported: a saved program is reused by a later process without tracing it again."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxdamp.cli import exported
from jaxdamp.runtime import batch_jit

from helpers import assert_tree_allclose

TRACES = []


@batch_jit
def _program(x, pair):
    TRACES.append(1)  # runs only while tracing
    return {"sum": x + pair[0], "loop": jax.lax.while_loop(lambda c: c < 10.0,
                                                          lambda c: c + pair[1], 0.0)}


def test_saved_export_is_reused_without_tracing(monkeypatch, tmp_path):
    monkeypatch.setenv("JAXDAMP_CACHE_DIR", str(tmp_path))
    args = (jnp.arange(3.0), (jnp.asarray(1.5), jnp.asarray(3.0)))
    first = exported.call("toy", _program, args)
    saved = list((tmp_path / "exported").iterdir())
    assert len(saved) == 1 and saved[0].name.startswith("toy-")
    n = len(TRACES)
    exported.forget_loaded()  # as in a new process: only the file is left
    # New values, same shapes: the saved program, not a new trace of _program.
    second = exported.call("toy", _program, (jnp.arange(3.0) + 1.0, (jnp.asarray(2.0),
                                                                     jnp.asarray(4.0))))
    assert len(TRACES) == n
    np.testing.assert_array_equal(first["sum"], np.arange(3.0) + 1.5)
    np.testing.assert_array_equal(second["sum"], np.arange(3.0) + 3.0)
    assert float(first["loop"]) == 12.0 and float(second["loop"]) == 12.0
    # Another variant (static options) or shape is another file.
    exported.call("toy", _program, (jnp.arange(4.0), args[1]))
    exported.call("toy", _program, args, variant="other")
    assert len(list((tmp_path / "exported").iterdir())) == 3


def _scaled_program(factor):
    """One program per factor: its closure's constant, as `bands_program`'s options are."""
    return jax.jit(lambda x: x * factor)


def test_one_name_for_programs_of_other_options_keeps_them_apart(monkeypatch, tmp_path):
    """The study saves all its programs under one name: a program's function and the constants of
    its closure (its static options) are part of the key, so that programs of the same inputs'
    shapes but other options never share a file."""
    monkeypatch.setenv("JAXDAMP_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(exported, "SHIPPED_DIR", tmp_path / "none")
    x = jnp.arange(3.0)
    np.testing.assert_array_equal(exported.call("same", _scaled_program(2.0), (x,)), 2.0 * x)
    np.testing.assert_array_equal(exported.call("same", _scaled_program(3.0), (x,)), 3.0 * x)
    exported.forget_loaded()  # as in a new process: only the files are left
    np.testing.assert_array_equal(exported.call("same", _scaled_program(3.0), (x,)), 3.0 * x)
    np.testing.assert_array_equal(exported.call("same", _scaled_program(2.0), (x,)), 2.0 * x)
    assert len(list((tmp_path / "exported").iterdir())) == 2


def test_a_program_closing_over_an_array_is_not_saved(monkeypatch, tmp_path):
    """An array in a closure would be baked into the saved program, unseen by the key: such a
    program runs as a plain call and nothing is written."""
    monkeypatch.setenv("JAXDAMP_CACHE_DIR", str(tmp_path))
    offset = jnp.asarray([1.0, 2.0])
    program = jax.jit(lambda x: x + offset)
    assert exported.program_identity(program) is None
    assert exported.program_identity(_scaled_program(2.0)) is not None
    np.testing.assert_array_equal(exported.call("toy", program, (jnp.zeros(2),)), [1.0, 2.0])
    assert not (tmp_path / "exported").exists()


def test_the_clis_programs_have_an_identity_and_are_saved():
    """Every program factory whose programs the CLI saves gives programs with an identity (else
    they would run unsaved), and two option sets give two identities."""
    from jaxdamp.band import bands_program
    from jaxdamp.cli.cycle import cycle_program
    from jaxdamp.ellipse import sweep_program
    from jaxdamp.response import peak_program
    from jaxdamp.response.diagram import diagram_program
    from jaxdamp.response.peaks import curves_program, path_curves_program
    from jaxdamp.response.row import row_program
    from jaxdamp.response.row_band import row_band_program

    pairs = [(bands_program(64, 6, 2), bands_program(32, 6, 2)),
             (peak_program("exact"), peak_program("interpolated")),
             (diagram_program("exact"), diagram_program("interpolated")),
             (curves_program("exact"), curves_program("interpolated")),
             (path_curves_program("assembly"), path_curves_program("gross_slip")),
             (row_program("assembly"), row_program("gross_slip")),
             (row_band_program(64), row_band_program(32)),
             (sweep_program("assembly"), sweep_program("gross_slip"))]
    for a, b in pairs:
        ids = exported.program_identity(a), exported.program_identity(b)
        assert None not in ids and ids[0] != ids[1], ids
    assert exported.program_identity(cycle_program()) is not None


def test_a_shipped_program_serves_an_empty_cache_folder_without_tracing(monkeypatch, tmp_path):
    """A program saved with the package (exported.SHIPPED_DIR) is what a new cache folder runs:
    no trace, no export; the user's folder stays empty of exports."""
    shipped, user = tmp_path / "shipped", tmp_path / "user"
    monkeypatch.setenv("JAXDAMP_CACHE_DIR", str(tmp_path / "maker"))
    args = (jnp.arange(3.0), (jnp.asarray(1.5), jnp.asarray(3.0)))
    exported.call("toy", _program, args)
    shipped.mkdir()
    for saved in (tmp_path / "maker" / "exported").iterdir():
        saved.rename(shipped / saved.name)
    monkeypatch.setattr(exported, "SHIPPED_DIR", shipped)
    monkeypatch.setenv("JAXDAMP_CACHE_DIR", str(user))
    exported.forget_loaded()
    n = len(TRACES)

    def no_export(*a, **k):
        raise AssertionError("traced and exported again")

    monkeypatch.setattr(exported.jexport, "export", no_export)
    out = exported.call("toy", _program, (jnp.arange(3.0) + 1.0, args[1]))
    assert len(TRACES) == n and not (user / "exported").exists()
    np.testing.assert_array_equal(out["sum"], np.arange(3.0) + 2.5)


def test_shipped_programs_match_the_sources():
    """The programs saved with the package were saved by these sources (their key holds the
    sources' digest, so stale ones are never used, only useless): after a change to jaxdamp, run
    `python scripts/export_programs.py`."""
    import json

    manifest = json.loads((exported.SHIPPED_DIR / "manifest.json").read_text())
    files = sorted(p.name for p in exported.SHIPPED_DIR.glob("*.bin"))
    assert files == sorted(manifest["programs"])
    assert {f.split("-")[0] for f in files} >= {"cycle", "grad_fwd", "response_curves", "band_grid",
                                              "fit_loops"}
    if (manifest["jax"], manifest["platform"]) != (jax.__version__, jax.default_backend()):
        pytest.skip(f"saved for jax {manifest['jax']} on {manifest['platform']}: not used here")
    assert manifest["sources"] == exported.sources_digest(), (
        "the programs in jaxdamp/data/exported are older than the sources: run "
        "`python scripts/export_programs.py`")


def test_the_shipped_cycle_gives_the_librarys_numbers(monkeypatch, tmp_path):
    """The `cycle` command's program in a new cache folder is the shipped one (no export), and its
    five numbers are those of the library's own Base-Cycle."""
    import json

    import jaxdamp as jd
    from jaxdamp.cli.cycle import cycle_program
    from jaxdamp.params import prepare_inputs

    manifest = json.loads((exported.SHIPPED_DIR / "manifest.json").read_text())
    if manifest["sources"] != exported.sources_digest() or manifest["jax"] != jax.__version__:
        pytest.skip("the shipped programs are not for these sources (see the test above)")
    monkeypatch.setenv("JAXDAMP_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(exported.jexport, "export", None)  # any export would fail
    exported.forget_loaded()
    inputs = prepare_inputs(jd.family_shape("74R"), 0.5, jd.Contacts(), jd.LoadCase())
    _, shipped, _, _ = exported.call("cycle", cycle_program(), inputs)
    nums = jd.five_numbers(jd.base_cycle(jd.family_shape("74R"), 0.5))
    assert_tree_allclose(shipped, nums, rtol=1e-9, atol=1e-9)
    assert int(nums.status) == 0 and not (tmp_path / "exported").exists()


def test_cache_off_is_a_plain_call(monkeypatch, tmp_path):
    monkeypatch.setenv("JAXDAMP_CACHE_DIR", "off")
    out = exported.call("toy", _program, (jnp.arange(2.0), (jnp.asarray(1.0), jnp.asarray(5.0))))
    np.testing.assert_array_equal(out["sum"], [1.0, 2.0])


@pytest.mark.slow  # 90 worker-s (loaded run, 2026-11-26): the grad program twice
def test_grad_through_a_saved_export_equals_the_plain_call(monkeypatch, tmp_path):
    """`jaxdamp grad` runs its Jacobian program through a saved export (a repeat process neither
    traces nor lowers it); its derivatives are the plain program's."""
    import jaxdamp as jd
    from jaxdamp.cli.grad import grad_payload

    args = (jd.family_shape("74R"), 0.5, jd.Contacts(), jd.LoadCase())
    monkeypatch.setenv("JAXDAMP_CACHE_DIR", "off")
    monkeypatch.setattr(exported, "SHIPPED_DIR", tmp_path / "none")  # the user's folder only
    status_plain, plain = grad_payload(*args)
    monkeypatch.setenv("JAXDAMP_CACHE_DIR", str(tmp_path))
    status_saved, saved = grad_payload(*args)
    assert [p.name.split("-")[0] for p in (tmp_path / "exported").iterdir()] == ["grad_fwd"]
    exported.forget_loaded()  # as in a new process: only the file is left
    status_again, again = grad_payload(*args)
    assert status_plain == status_saved == status_again == "ok"
    for key in ("psi_bc_mrad", "k_im_bc", "k_re_bc", "psi_fs_mrad", "k_re_fs"):
        # The export compiles its own program: rounding may differ, relative to the output's
        # largest derivative (a derivative that is zero in exact arithmetic comes out ~1e-15).
        scale = max(np.max(np.abs(np.asarray(v, float))) for v in plain[key].values())
        for var, value in plain[key].items():
            for got in (saved, again):
                assert_tree_allclose(got[key][var], value, rtol=1e-12, atol=1e-12 * scale,
                                     err_msg=(key, var))
    assert abs(plain["k_im_bc"]["theta_l"]) > 0  # a derivative that is not trivially zero


def test_a_runners_compile_ahead_leaves_the_call_nothing_to_trace_or_compile(monkeypatch, tmp_path):
    """`Runner.compile_ahead` loads (here: exports and saves) and compiles the program for the
    inputs' shapes; the runner's later call with other values of those shapes reads the same
    file and neither traces nor compiles."""
    from helpers import count_compiles

    monkeypatch.setenv("JAXDAMP_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(exported, "SHIPPED_DIR", tmp_path / "none")
    runner = exported.Runner("ahead", "v1")
    placeholder = (jnp.zeros(3), (jnp.asarray(0.0), jnp.asarray(0.0)))
    runner.compile_ahead(_program, placeholder)
    saved = list((tmp_path / "exported").iterdir())
    assert len(saved) == 1 and saved[0].name.startswith("ahead-")
    n = len(TRACES)
    args = (jnp.arange(3.0), (jnp.asarray(1.5), jnp.asarray(3.0)))
    with count_compiles() as compiled:
        out = runner(_program, args)
    assert compiled == [] and len(TRACES) == n
    assert list((tmp_path / "exported").iterdir()) == saved
    np.testing.assert_array_equal(out["sum"], np.arange(3.0) + 1.5)
    assert float(out["loop"]) == 12.0


@batch_jit
def _halve(x, scale):
    return x * 0.5, scale


def test_a_saved_programs_own_outputs_fed_back_compile_nothing(monkeypatch, tmp_path):
    """A saved program's outputs come back committed to a device (they carry the export's
    shardings) and JAX compiles a jitted function anew for a committed input it first saw
    uncommitted: the fit's solver step, fed its own theta back, compiled twice (4.7 s each). Every
    call gets its inputs committed, so that a loop feeding outputs back compiles once."""
    from helpers import count_compiles

    monkeypatch.setenv("JAXDAMP_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(exported, "SHIPPED_DIR", tmp_path / "none")
    runner = exported.Runner("loop")
    x, scale = runner(_halve, (jnp.arange(4.0), jnp.asarray(2.0, float)))
    with count_compiles() as compiled:
        for _ in range(3):
            x, scale = runner(_halve, (x, scale))
    assert compiled == []
    np.testing.assert_array_equal(x, np.arange(4.0) / 16.0)
