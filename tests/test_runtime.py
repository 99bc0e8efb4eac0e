"""jaxdamp.runtime: the measured compiler options reach the batched programs, are dropped where XLA
rejects them, change no result beyond rounding, and importing jaxdamp starts no backend."""

import os
import subprocess
import sys

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp import batch as B
from jaxdamp import runtime

from helpers import assert_tree_allclose, count_compiles


@pytest.fixture
def fresh_options():
    runtime.batch_compiler_options.cache_clear()
    yield
    runtime.batch_compiler_options.cache_clear()


def _summary_hlo(compile_fn, n=1024):
    # XLA hands reductions to YNNPACK above a size: a CPU chunk of designs is above it.
    designs = jd.stack_designs(jd.DamperShape(np.full(n, 60.0), np.full(n, 55.0), np.zeros(n),
                                              np.full(n, 0.8)), 0.5)
    return compile_fn(jax.vmap(B.first_stage_summary)).lower(designs).compile().as_text()


def test_cpu_batches_compile_without_library_reductions(fresh_options):
    if jax.default_backend() != "cpu":
        pytest.skip("the options are for the CPU backend")
    if not runtime.batch_compiler_options():
        pytest.skip("this XLA does not know the measured option: it runs with XLA's defaults "
                    "(measure again with benchmarks/bench_runtime_options.py)")
    assert runtime.batch_compiler_options() == runtime.CPU_BATCH_OPTIONS
    assert "ynn_fusion" not in _summary_hlo(runtime.batch_jit)


def test_rejected_options_fall_back_to_xla_defaults(fresh_options, monkeypatch):
    monkeypatch.setattr(runtime, "CPU_BATCH_OPTIONS",
                        {"xla_cpu_experimental_ynn_fusion_type": "not-a-fusion-type"})
    assert runtime.batch_compiler_options() == {}
    f = runtime.batch_jit(lambda x: jnp.sum(x * x, axis=-1))
    np.testing.assert_array_equal(f(jnp.ones((4, 3))), np.full(4, 3.0))


def test_a_programs_own_options_reach_its_compilation(fresh_options, monkeypatch):
    """batch_jit(cpu_options=...): the program's options join the batch options where XLA takes
    them; options this XLA rejects leave the batch options alone (the row's derivative program
    asks for `LOOP_EMITTERS`, and so does its saved form, `jaxdamp.cli.exported`)."""
    if jax.default_backend() != "cpu" or not runtime.batch_compiler_options():
        pytest.skip("the options are for the CPU backend's XLA that knows them")
    own = tuple(runtime.LOOP_EMITTERS.items())
    assert runtime.batch_compiler_options(own) == {**runtime.CPU_BATCH_OPTIONS,
                                                   **runtime.LOOP_EMITTERS}
    assert runtime.batch_compiler_options((("xla_not_an_option", 1),)) == runtime.CPU_BATCH_OPTIONS
    seen = []
    real_jit = jax.jit
    monkeypatch.setattr(runtime.jax, "jit", lambda f, **kw: seen.append(kw) or real_jit(f, **kw))
    f = runtime.batch_jit(lambda x: 2.0 * x, cpu_options=runtime.LOOP_EMITTERS)
    assert float(f(3.0)) == 6.0 and f.cpu_options == own
    assert seen[-1]["compiler_options"] == {**runtime.CPU_BATCH_OPTIONS, **runtime.LOOP_EMITTERS}
    from jaxdamp.response.row_gradient import row_gradient_program
    assert row_gradient_program("assembly", False).cpu_options == own


def test_decorator_forms_pass_jit_arguments():
    @runtime.batch_jit(static_argnames=("power",))
    def f(x, power):
        return x ** power

    @runtime.batch_jit
    def g(x):
        return 2.0 * x

    assert float(f(3.0, power=2)) == 9.0 and float(g(3.0)) == 6.0
    assert f.__name__ == "f" and f.lower(2.0, power=3).compile()(2.0) == 8.0


@pytest.mark.slow  # 19 worker-s (run of 2026-11-25)
def test_batched_results_equal_plain_jit_to_rounding():
    rng = np.random.default_rng(3)
    n = 64
    designs = jd.stack_designs(jd.DamperShape(rng.uniform(35, 90, n), rng.uniform(35, 90, n),
                                              rng.uniform(-0.3, 0.4, n), np.full(n, 0.8)),
                               rng.uniform(0.1, 0.9, n))
    fast = jax.device_get(runtime.batch_jit(jax.vmap(B.first_stage_summary))(designs))
    plain = jax.device_get(jax.jit(jax.vmap(B.first_stage_summary))(designs))
    for a, b in zip(fast, plain):
        if np.issubdtype(np.asarray(a).dtype, np.floating):
            assert_tree_allclose(a, b, rtol=1e-11, atol=1e-9)
        else:
            np.testing.assert_array_equal(a, b)


def test_values_chunk_is_larger_on_cpu_only():
    assert B.VALUES_CHUNK_BY_PLATFORM["cpu"] > B.default_chunk("cpu")
    expected = B.VALUES_CHUNK_BY_PLATFORM.get(jax.devices()[0].platform)
    assert B.values_chunk() == expected


def test_import_starts_no_backend():
    code = ("import jaxdamp, jaxdamp.batch, jaxdamp.amplitude, jaxdamp.response\n"
            "from jax._src import xla_bridge\n"
            "print(xla_bridge.backends_are_initialized())")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_one_padding_rule():
    """runtime.padded_size, the padding of every batched call: never below n, a short ladder of
    sizes (power-of-two steps: the next power of two; eight steps per octave: at most 1/8 waste)."""
    from jaxdamp.runtime import padded_size

    for n in range(1, 5000):
        pow2 = padded_size(n, 8)
        assert pow2 >= max(n, 8) and pow2 & (pow2 - 1) == 0 and pow2 < 2 * max(n, 8)
        fine = padded_size(n, 16, 8)
        assert fine >= n and fine % 16 == 0 and (fine - n) <= max(16, n / 8)
    assert len({padded_size(n, 8) for n in range(1, 1025)}) == 8  # 8, 16, ..., 1024


def test_compile_for_latency_adds_its_flags_and_keeps_the_users(monkeypatch):
    monkeypatch.delenv("JAX_PLATFORMS", raising=False)
    monkeypatch.setenv("XLA_FLAGS", "--xla_backend_optimization_level=2")
    assert runtime.compile_for_latency()
    flags = os.environ["XLA_FLAGS"].split()
    # The user's level stays; the flag they did not set is added, once.
    assert flags == ["--xla_backend_optimization_level=2", "--xla_cpu_use_fusion_emitters=false"]
    assert not runtime.compile_for_latency()
    monkeypatch.delenv("XLA_FLAGS")
    assert runtime.compile_for_latency()
    assert sorted(os.environ["XLA_FLAGS"].split()) == [
        "--xla_backend_optimization_level=0", "--xla_cpu_use_fusion_emitters=false"]


def test_compile_for_latency_leaves_other_platforms_alone(monkeypatch):
    monkeypatch.setenv("JAX_PLATFORMS", "cuda")
    monkeypatch.delenv("XLA_FLAGS", raising=False)
    assert not runtime.compile_for_latency()
    assert "XLA_FLAGS" not in os.environ


def test_fast_compiled_cycle_equals_the_optimised_one():
    """The latency options change how XLA optimises, not what it computes: the Base-Cycle's five
    numbers of two designs agree with the default compilation to rounding (the event chain
    amplifies a last-bit difference by its conditioning, far below 1e-10)."""
    from jaxdamp.cycle import base_cycle_kernel
    from jaxdamp.harmonics import five_numbers_kernel
    from jaxdamp.params import prepare_inputs

    def numbers(*inputs):
        return five_numbers_kernel(base_cycle_kernel(*inputs))

    for name, mu in (("74R", 0.5), ("60sym", 0.3)):
        inputs = prepare_inputs(jd.family_shape(name), mu, jd.Contacts(), jd.LoadCase())
        fast = jax.jit(numbers, compiler_options=runtime.LATENCY_OPTIONS)(*inputs)
        optimised = jax.jit(numbers)(*inputs)
        assert_tree_allclose(fast, optimised, rtol=1e-10, atol=1e-12)


def test_side_by_side_runs_the_calls_at_once_and_returns_them_in_order():
    """runtime.side_by_side: every call runs at the same time as the others (three calls meet at
    a barrier, which only concurrent calls can pass), results in the calls' order, and the first
    exception reaches the caller."""
    import threading

    meet = threading.Barrier(3, timeout=30)

    def call(value):
        def run():
            meet.wait()
            return value
        return run

    assert runtime.side_by_side(call("a"), call("b"), call("c")) == ["a", "b", "c"]
    assert runtime.side_by_side(lambda: 1) == [1]

    def fails():
        raise ValueError("the second call's error")

    with pytest.raises(ValueError, match="second call"):
        runtime.side_by_side(lambda: 1, fails)


def test_thread_map_runs_up_to_its_threads_at_once_in_order():
    """runtime.thread_map: `threads` items at the same time (two meet at a barrier that only
    concurrent calls pass; a third thread is never asked for), the results in the items' order,
    one thread or one item on the calling thread, and an item's exception reaches the caller."""
    import threading

    meet = threading.Barrier(2, timeout=30)
    running, most = [0], [0]
    lock = threading.Lock()

    def work(x):
        with lock:
            running[0] += 1
            most[0] = max(most[0], running[0])
        meet.wait()
        with lock:
            running[0] -= 1
        return 10 * x

    assert runtime.thread_map(work, range(6), 2) == [0, 10, 20, 30, 40, 50]
    assert most[0] == 2
    caller = threading.get_ident()
    assert runtime.thread_map(lambda x: threading.get_ident(), [1, 2], 1) == [caller, caller]
    assert runtime.thread_map(lambda x: threading.get_ident(), [1], 4) == [caller]
    assert runtime.thread_map(work, [], 2) == []

    def fails(x):
        if x == 3:
            raise ValueError("item 3's error")
        return x

    with pytest.raises(ValueError, match="item 3"):
        runtime.thread_map(fails, range(5), 2)
    assert runtime.cpu_cores() >= 1


def test_map_in_parts_runs_parts_of_one_shape_trimmed_in_order(monkeypatch):
    """On the CPU every part is cpu_chunk long (the last padded by repeating its first entry),
    elsewhere one part padded to padded_size; the outputs come back trimmed, in order, for a
    pytree of outputs too."""
    seen = []

    def run(part):
        seen.append(part.copy())
        return {"twice": 2 * part, "rows": np.stack([part, -part], axis=1)}

    items = np.arange(10, 17)
    out = runtime.map_in_parts(run, items, 3)
    assert [p.tolist() for p in sorted(seen, key=lambda p: p[0])] == [[10, 11, 12], [13, 14, 15],
                                                                      [16, 16, 16]]
    assert out["twice"].tolist() == (2 * items).tolist()
    assert out["rows"].tolist() == np.stack([items, -items], axis=1).tolist()
    seen.clear()
    monkeypatch.setattr(runtime.jax, "default_backend", lambda: "gpu")
    out = runtime.map_in_parts(run, items, 3, min_step=16)
    assert [p.tolist() for p in seen] == [list(range(10, 17)) + [10] * 9]
    assert out["twice"].tolist() == (2 * items).tolist()


def test_run_program_calls_the_program_or_hands_it_to_the_runner():
    """The one `runner=` protocol: without a runner the program's own call, with one the runner
    gets the program and its arguments and its result is returned."""
    from jaxdamp.runtime import run_program

    def program(a, b):
        return a + b

    seen = []

    def runner(prog, args):
        seen.append((prog, args))
        return "from the runner"

    assert run_program(program, (2, 3)) == 5 and not seen
    assert run_program(program, (2, 3), runner) == "from the runner"
    assert seen == [(program, (2, 3))]


def test_compile_ahead_compiles_for_the_later_call_on_a_thread(monkeypatch):
    """compile_ahead compiles a program on a thread for its inputs' shapes and dtypes (the values
    are not used): the later call with other values of those shapes neither traces nor compiles
    and gives the program's values. A runner with a compile_ahead method gets the program and
    the inputs there; one without compiles nothing ahead; an error on the thread is dropped (the
    later call raises it)."""
    traces = []

    @jax.jit
    def program(x, scale):
        traces.append(1)  # runs only while tracing
        return jnp.sin(x) * scale

    thread = runtime.compile_ahead(program, (np.zeros(5), np.zeros(())))
    thread.join()
    assert len(traces) == 1
    x = np.linspace(0.0, 1.0, 5)
    args = (jnp.asarray(x), jnp.asarray(2.0, float))  # float64, not weakly typed: as placeholder's
    with count_compiles() as compiled:
        out = program(*args)
    assert compiled == [] and len(traces) == 1
    assert_tree_allclose(out, 2.0 * np.sin(x), rtol=1e-15, atol=0.0)

    assert runtime.compile_ahead(program, (x, 1.0), lambda prog, args: None) is None
    seen = []

    class Runner:
        def __call__(self, prog, args):
            return prog(*args)

        def compile_ahead(self, prog, args):
            seen.append((prog, args))

    runtime.compile_ahead(program, (x, 1.0), Runner()).join()
    assert seen == [(program, (x, 1.0))]

    raised = []
    monkeypatch.setattr("threading.excepthook", raised.append)

    @jax.jit
    def broken(x):
        raise RuntimeError("traced")

    runtime.compile_ahead(broken, (x,)).join()
    assert raised == []
    with pytest.raises(RuntimeError, match="traced"):
        broken(x)
