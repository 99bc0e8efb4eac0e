"""The slow tier's shards (tests/conftest.py, tests/slow_shards.json, scripts/slow_shards.py): the
table CI picks its shard from is whole and consistent, and the script that writes it reads both
kinds of duration record and balances as it says."""

import importlib.util
import json
from pathlib import Path

import pytest

from conftest import SLOW_SECONDS, SHARDS_FILE, slow_shard_of, slow_shards

ROOT = Path(__file__).resolve().parent.parent


def _script():
    spec = importlib.util.spec_from_file_location("slow_shards", ROOT / "scripts" / "slow_shards.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_table_is_whole_and_consistent():
    """Every shard index is in range, the per-shard loads are the sums of the tests' seconds, and
    a test slow by measure is assigned a shard and measured over the threshold."""
    table = json.loads(SHARDS_FILE.read_text())
    n_shards, assigned, by_measure = slow_shards()
    assert n_shards == len(table["worker_seconds_per_shard"]) >= 2
    assert all(0 <= k < n_shards for k in assigned.values())
    assert set(by_measure) <= set(assigned)
    assert all(s > SLOW_SECONDS for s in by_measure.values())
    seconds = table["seconds"]
    assert set(seconds) == set(assigned)
    load = [0.0] * n_shards
    for nodeid, k in assigned.items():
        load[k] += seconds[nodeid]
    assert load == pytest.approx(table["worker_seconds_per_shard"], abs=0.05 * len(assigned))
    assert _script().SLOW_SECONDS == SLOW_SECONDS


def test_an_unnamed_slow_test_gets_a_stable_shard():
    n_shards = slow_shards()[0]
    k = slow_shard_of("tests/test_x.py::test_not_in_the_table", {}, n_shards)
    assert 0 <= k < n_shards
    assert k == slow_shard_of("tests/test_x.py::test_not_in_the_table", {}, n_shards)
    assert slow_shard_of("tests/test_x.py::named", {"tests/test_x.py::named": 1}, n_shards) == 1


def test_durations_are_read_from_junit_and_from_pytest_output(tmp_path):
    """Setup, call and teardown summed per test; a skipped case is no measure."""
    script = _script()
    xml = tmp_path / "run.xml"
    xml.write_text('<?xml version="1.0"?><testsuites><testsuite>'
                   '<testcase classname="tests.test_a" name="test_one[x-1]" time="12.5"/>'
                   '<testcase classname="tests.test_a" name="test_two" time="0.5">'
                   '<skipped message="no"/></testcase></testsuite></testsuites>')
    assert script.durations(xml) == {"tests/test_a.py::test_one[x-1]": 12.5}
    log = tmp_path / "run.log"
    log.write_text("== slowest durations ==\n"
                   "10.00s call     tests/test_a.py::test_one[x-1]\n"
                   "2.50s setup    tests/test_a.py::test_one[x-1]\n"
                   "0.10s teardown tests/test_b.py::test_three\n"
                   "6.00s call     tests/test_b.py::test_four[curved-flat out-of-phase]\n")
    assert script.durations(log) == {"tests/test_a.py::test_one[x-1]": 12.5,
                                     "tests/test_b.py::test_three": 0.1,
                                     "tests/test_b.py::test_four[curved-flat out-of-phase]": 6.0}


def test_balance_places_longest_first_within_four_thirds_of_the_best():
    """The greedy rule: every test placed once, and the largest shard within 4/3 of the lower
    bound max(total / n, longest test)."""
    seconds = {f"t{i}": float(s) for i, s in enumerate([90, 70, 65, 40, 33, 30, 22, 20, 15, 9, 8,
                                                        5, 5, 3, 1])}
    shards, load = _script().balance(seconds, 4)
    assert set(shards) == set(seconds) and all(0 <= k < 4 for k in shards.values())
    assert sum(load) == pytest.approx(sum(seconds.values()))
    best = max(sum(seconds.values()) / 4, max(seconds.values()))
    assert max(load) <= 4 / 3 * best


def test_a_file_s_slow_tests_share_a_shard_unless_they_outweigh_an_average_one():
    """A file's tests are one unit (its module fixtures are paid once); a file heavier than the
    average shard is split into its tests, so no shard is forced over the average by one file."""
    seconds = {"tests/a.py::x": 30.0, "tests/a.py::y": 0.0, "tests/a.py::z": 5.0,
               "tests/b.py::p": 50.0, "tests/b.py::q": 50.0,
               "tests/c.py::r": 20.0, "tests/d.py::s": 15.0}
    shards, load = _script().balance(seconds, 3)  # the average shard: 170 / 3 = 56.7 s
    assert shards["tests/a.py::x"] == shards["tests/a.py::y"] == shards["tests/a.py::z"]
    assert shards["tests/b.py::p"] != shards["tests/b.py::q"]
    assert sorted(load) == [50.0, 55.0, 65.0]


def test_a_bad_shard_is_one_usage_line_before_any_test():
    """`--slow-shard` out of range or not a number: pytest's usage error (exit 4), one line naming
    the option and its range, under xdist too (not an INTERNALERROR traceback)."""
    import subprocess
    import sys

    run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-n", "2",
                          "--slow-shard", "all", "tests/test_slow_shards.py"],
                         capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert run.returncode == 4, run.stdout + run.stderr
    assert "--slow-shard must be auto or an integer in [0, " in run.stderr
    assert "INTERNALERROR" not in run.stdout + run.stderr
