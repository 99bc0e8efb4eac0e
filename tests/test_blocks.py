"""jaxdamp.blocks: the building blocks behind the entry points, in a namespace of their own; the
top level lists the library by concept in at most 110 names (issue 62). Names that moved still
resolve at the top level, with a DeprecationWarning naming their new place."""

import importlib

import pytest

import jaxdamp as jd


def test_the_top_level_lists_at_most_110_names_none_twice():
    assert len(jd.__all__) <= 110
    assert len(set(jd.__all__)) == len(jd.__all__)
    assert not set(jd.__all__) & set(jd.blocks.__all__)


@pytest.mark.parametrize("name", sorted(jd.blocks.__all__))
def test_a_moved_name_is_the_same_object_with_a_warning(name):
    block = getattr(jd.blocks, name)
    with pytest.warns(DeprecationWarning, match=f"jaxdamp.blocks.{name}"):
        assert getattr(jd, name) is block
    # defined once, in the module that computes it: blocks only re-exports
    module = getattr(block, "__module__", None)
    if module is not None and module != "builtins":
        assert importlib.import_module(module) is not jd.blocks


def test_merged_twins_point_at_the_one_function():
    with pytest.warns(DeprecationWarning, match=r"amplitude_curves\(\.\.\., method='sequence'\)"):
        jd.sequence_curves
    with pytest.warns(DeprecationWarning, match="amplitude_band with a grid"):
        jd.amplitude_bands
    with pytest.warns(DeprecationWarning, match="jaxdamp.blocks.Half"):
        assert jd.HalfCycle is jd.blocks.Half
    with pytest.raises(AttributeError, match="no attribute 'no_such_name'"):
        jd.no_such_name


def test_amplitude_curves_takes_one_method_of_two():
    with pytest.raises(ValueError, match="method must be one of cycles, sequence; got 'fast'"):
        jd.amplitude_curves(jd.family_shape("60sym"), 0.5, [1.0], method="fast")
