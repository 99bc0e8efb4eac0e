"""The modal file (`jaxdamp.modal_file`): NPZ and JSON round trips, SI units, the example disk's
file, and one-line refusals naming the field. Numpy only: nothing here compiles."""

import json
from pathlib import Path

import numpy as np
import pytest

from helpers import assert_tree_allclose
from jaxdamp.modal_file import family_from_mapping, load_modal_family, save_modal_family
from jaxdamp.response import BladeMode
from jaxdamp.response.modes import ModalFamily, family_from_blade_mode, nodal_scene

EXAMPLE = Path(__file__).resolve().parents[1] / "jaxdamp" / "data" / "example_disk_modes.npz"


def _family():
    f = family_from_blade_mode(BladeMode(), 100.0, 40.0, 10)
    rep = lambda v: np.repeat(v, 3, axis=0)  # noqa: E731
    return ModalFamily(10, np.array([0, 2, 5]), np.array([500.0, 610.0, 640.0]),
                       np.array([1e-3, 2e-3, 1e-3]), rep(f.modal_force) * np.array([1, 1j, -1]),
                       rep(f.response_displacement), rep(f.left_platform) * (1 + 0.5j),
                       rep(f.right_platform), "three rows", _residual())


def _residual():
    """A Hermitian positive-definite flexibility per row, (mm, mm, rad) per (N, N, N mm)."""
    rng = np.random.default_rng(3)
    a = rng.normal(size=(3, 6, 6)) + 1j * rng.normal(size=(3, 6, 6))
    scale = np.tile([1e-4, 1e-4, 1e-8], 2)  # mm/N and rad/(N mm) sized entries
    return scale[None, :, None] * (a @ np.conj(np.swapaxes(a, 1, 2))) * scale[None, None, :]


def _fields(fam):
    return [np.asarray(getattr(fam, k)) for k in ModalFamily._fields[1:8] + ("platform_residual",)]


@pytest.mark.parametrize("suffix", [".npz", ".json"])
def test_round_trip(tmp_path, suffix):
    fam = _family()
    back = load_modal_family(save_modal_family(fam, tmp_path / f"modes{suffix}"))
    assert back.n_blades == 10 and back.name == "three rows"
    assert_tree_allclose(_fields(back), [np.asarray(v, dtype=np.asarray(w).dtype) for v, w in
                                         zip(_fields(fam), _fields(back))], rtol=1e-15, atol=0.0)


def test_si_units_give_the_same_reduction(tmp_path):
    """The same modes mass-normalised in m, N, s, kg: a unit modal coordinate is sqrt(1000) times
    larger (1 kg^0.5 m = sqrt(1000) t^0.5 mm), so a length per unit coordinate, written in m, is
    1/sqrt(1000) times its mm-t number (a 1 kg mass: 1 m vs 31.6 mm), a rotation sqrt(1000) times,
    a modal force 1/sqrt(1000) times. The blade, path and tip force of every engine order must not
    change."""
    fam = _family()
    r = np.sqrt(1000.0)
    doc = json.loads(save_modal_family(fam, tmp_path / "mm.json").read_text())
    cplx = lambda v: np.asarray(v["re"]) + 1j * np.asarray(v["im"])  # noqa: E731
    si = dict(doc, unit_system="SI")
    si["modal_force"] = cplx(doc["modal_force"]) / r
    si["response_displacement"] = cplx(doc["response_displacement"]) / r
    for side in ("left_platform", "right_platform"):
        si[side] = cplx(doc[side]) * np.array([1 / r, 1 / r, r])
    # The residual flexibility is physical, not modal: m/N is 1e-3 mm/N, rad/(N m) 1e3 rad/(N mm),
    # m/(N m) and rad/N the same numbers.
    kind = np.tile([0, 0, 1], 2)  # translation (0) or rotation (1), per row and column
    per_kinds = np.array([[1e-3, 1.0], [1.0, 1e3]])  # m/N, m/(N m) | rad/N, rad/(N m) in mm-N
    si["platform_residual"] = cplx(doc["platform_residual"]) * per_kinds[np.ix_(kind, kind)]
    si_fam = family_from_mapping(si)
    for e in (0, 2, 5, 8):
        a, b = nodal_scene(fam, e, 100.0, 30.0), nodal_scene(si_fam, e, 100.0, 30.0)
        assert_tree_allclose([np.array(list(b.mode)), np.array(b.force_per_unit),
                              np.array(b.residual_mrad_per_nmm)],
                             [np.array(list(a.mode)), np.array(a.force_per_unit),
                              np.array(a.residual_mrad_per_nmm)], rtol=1e-12, atol=0.0)
    assert a.residual_mrad_per_nmm > 0


def test_example_disk_file_loads():
    fam = load_modal_family("example")  # the name of the file shipped with the package
    assert_tree_allclose(_fields(fam), _fields(load_modal_family(EXAMPLE)), rtol=0.0, atol=0.0)
    assert fam.n_blades == 24 and list(fam.nodal_diameter) == list(range(13))
    assert np.all(np.diff(fam.frequency_hz) >= 0)  # the first family stiffens with the disk's ND


@pytest.mark.parametrize("edit, needle", [
    (lambda d: d.pop("frequency_hz"), "must have the field frequency_hz"),
    (lambda d: d.update(colour="red"), "unknown field 'colour'"),
    (lambda d: d.update(unit_system="inch"), "unit_system must be one of mm-N-s-t, SI"),
    (lambda d: d.update(n_blades=2.5), "n_blades must be an integer"),
    (lambda d: d.update(modal_force={"re": [1, 2, 3]}), "modal_force must be a list, or an object"),
    (lambda d: d.update(loss_factor=[0.1, 0.1]), "loss_factor must have shape (3,)"),
])
def test_bad_files_are_refused_in_one_line(tmp_path, edit, needle):
    doc = json.loads(save_modal_family(_family(), tmp_path / "m.json").read_text())
    edit(doc)
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(doc))
    with pytest.raises(ValueError) as e:
        load_modal_family(bad)
    assert needle in str(e.value) and "\n" not in str(e.value)


def test_paths_are_checked(tmp_path):
    with pytest.raises(ValueError, match="modes must be an existing .npz or .json file"):
        load_modal_family(tmp_path / "none.npz")
    (tmp_path / "m.txt").write_text("x")
    with pytest.raises(ValueError, match="modes must be a .npz or .json file"):
        load_modal_family(tmp_path / "m.txt")
    (tmp_path / "m.json").write_text("{not json")
    with pytest.raises(ValueError, match="is not readable JSON"):
        load_modal_family(tmp_path / "m.json")
