"""The helpers the suite compares results with (tests/helpers.py): no broadcasting, no dtype
confusion, and a failure that names the leaf."""

import jax.numpy as jnp
import numpy as np
import pytest

from helpers import assert_leaf_close, assert_tree_allclose, tree_allclose


def test_close_values_pass():
    assert tree_allclose({"a": np.ones(3)}, {"a": np.ones(3) * (1 + 1e-14)})
    assert tree_allclose((jnp.arange(3.0), None), (np.arange(3.0), None))
    assert tree_allclose(np.array([1.0, 2.0]), np.array([1.0, 2.1]), rtol=0.0, atol=0.2)
    assert not tree_allclose(np.array([1.0, 2.0]), np.array([1.0, 2.1]), rtol=0.0, atol=0.05)
    assert_tree_allclose({"a": np.ones(3)}, {"a": np.ones(3)}, rtol=0.0, atol=0.0)


def test_shape_must_match_without_broadcasting():
    assert not tree_allclose({"a": np.ones(3)}, {"a": np.ones(1)})  # np.allclose would say True
    assert not tree_allclose({"a": np.ones(3)}, {"a": np.ones((3, 1))})
    assert not tree_allclose({"a": np.ones(3)}, {"a": 1.0})


def test_dtype_must_match_exactly():
    assert not tree_allclose(np.ones(3, np.float32), np.ones(3, np.float64))
    assert not tree_allclose(jnp.ones(3, jnp.float32), np.ones(3))
    assert not tree_allclose(np.ones(3, np.int64), np.ones(3))
    assert not tree_allclose({"a": np.array(True)}, {"a": np.array(1.0)})
    assert tree_allclose(np.array([True, False]), np.array([True, False]))


def test_structure_must_match():
    assert not tree_allclose({"a": np.ones(3)}, {"b": np.ones(3)})
    assert not tree_allclose([np.ones(3)], (np.ones(3),))
    assert not tree_allclose((np.ones(3), None), (np.ones(3), np.ones(3)))


def test_nan_is_equal_only_when_asked():
    x = np.array([1.0, np.nan])
    assert not tree_allclose(x, x.copy())
    assert tree_allclose(x, x.copy(), equal_nan=True)


def test_the_assertion_names_the_leaf_and_its_errors():
    got = {"k": (np.array([1.0, 2.0, 3.0]), np.array([4.0, 5.0]))}
    want = {"k": (np.array([1.0, 2.0, 3.0]), np.array([4.0, 5.5]))}
    with pytest.raises(AssertionError, match=r"case 7: \['k'\]\[1\]: 1 of 2 elements differ "
                                             r"\(first at \(1,\).*max abs error 0\.5, max rel error "
                                             r"0\.0909"):
        assert_tree_allclose(got, want, rtol=1e-12, atol=0.0, err_msg="case 7")
    with pytest.raises(AssertionError, match=r"dtype float32 vs float64"):
        assert_tree_allclose(np.ones(2, np.float32), np.ones(2), rtol=1e-3, atol=0.0)
    with pytest.raises(AssertionError, match=r"shape \(3,\) vs \(1,\)"):
        assert_tree_allclose(np.ones(3), np.ones(1), rtol=1e-3, atol=0.0)
    with pytest.raises(TypeError):  # the tolerances are part of what a test says
        assert_tree_allclose(np.ones(3), np.ones(3))


def test_assert_leaf_close_scales_by_the_array():
    assert_leaf_close("x", np.array([1.0, 1e-20]), np.array([1.0, 0.0]), rtol=1e-12)
    with pytest.raises(AssertionError):
        assert_leaf_close("x", np.array([1.0, 2.0]), np.array([1.0, 2.1]), rtol=1e-3)
    with pytest.raises(AssertionError):
        assert_leaf_close("n", np.array([1, 2]), np.array([1, 3]))


def test_no_test_file_compares_with_a_raw_allclose_unless_the_docs_say_why():
    """docs/architecture.md ("Comparisons") lists the test files that keep np.allclose,
    jnp.allclose or np.testing.assert_allclose, each with its reason; every other file compares
    through the helpers above."""
    import re
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    raw = re.compile(r"\b(?:np|jnp|numpy)\.(?:testing\.assert_allclose|allclose)\(|"
                     r"^from numpy\.testing import .*assert_allclose", re.M)
    calls = {f"tests/{p.name}" for p in sorted((root / "tests").glob("test_*.py"))
             if raw.search(p.read_text())}
    doc = (root / "docs" / "architecture.md").read_text()
    section = doc.split("- **Comparisons**", 1)[1].split("\n- **", 1)[0]
    kept = section.split("Files that keep raw calls:", 1)[1]
    listed = set(re.findall(r"`(tests/test_\w+\.py)`", kept))
    assert calls == listed, (sorted(calls - listed), sorted(listed - calls))
