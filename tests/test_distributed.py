"""Many processes: two processes on localhost under jax.distributed, each with two host devices,
give the same numbers as one process (the batching path shards over every process's devices)."""

import json
import os
import socket
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import jaxdamp as jd

from helpers import assert_tree_allclose

WORKER = textwrap.dedent("""
    import json, sys
    import jax
    jax.config.update("jax_enable_x64", True)
    jax.config.update("jax_cpu_collectives_implementation", "gloo")
    jax.distributed.initialize(coordinator_address="127.0.0.1:" + sys.argv[2], num_processes=2,
                               process_id=int(sys.argv[1]))
    import numpy as np
    import jaxdamp as jd
    sys.path.insert(0, sys.argv[3])
    from test_distributed import designs
    out = jd.evaluate_designs(designs())
    print("RESULT " + json.dumps({"devices": len(jax.devices()), "local": len(jax.local_devices()),
                                  "summary": {k: np.asarray(v).tolist() for k, v in out._asdict().items()}}))
""")


def designs(n=41):
    """Random designs plus 90R, whose frozen-mechanism cycle needs the second stage."""
    rng = np.random.default_rng(11)
    shape = jd.DamperShape(np.r_[rng.uniform(40, 90, n - 1), 40.9], np.r_[rng.uniform(40, 90, n - 1), 90.0],
                           np.r_[rng.uniform(-0.2, 0.3, n - 1), 0.0])
    return jd.stack_designs(shape, np.r_[rng.uniform(0.2, 0.8, n - 1), 0.5])


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.slow  # 54 worker-s (run of 2026-11-25)
def test_two_processes_give_the_numbers_of_one():
    env = dict(os.environ, XLA_FLAGS="--xla_force_host_platform_device_count=2", JAX_PLATFORMS="cpu")
    port = str(_free_port())
    here = os.path.dirname(__file__)
    procs = [subprocess.Popen([sys.executable, "-c", WORKER, str(i), port, here], env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for i in range(2)]
    results = []
    for p in procs:
        out, err = p.communicate(timeout=300)
        assert p.returncode == 0, err[-2000:]
        line = [ln for ln in out.splitlines() if ln.startswith("RESULT ")]
        assert line, out + err[-2000:]
        results.append(json.loads(line[0][len("RESULT "):]))
    one = jd.evaluate_designs(designs())
    for r in results:
        assert r["devices"] == 4 and r["local"] == 2
        for field, value in one._asdict().items():
            want = np.asarray(value, float)
            # Rounding level of each field's scale: 90R's k_Im is 0 up to ~1e-12 N mm/mrad on a
            # scale of 1e3-1e4, and its sign is rounding too.
            scale = np.max(np.abs(want)) or 1.0
            assert_tree_allclose(np.asarray(r["summary"][field], float), want, rtol=1e-12,
                                 atol=1e-14 * scale, err_msg=field)
    assert np.asarray(one.half_cycles)[-1] > 2  # the 90R row went through the second stage
