"""The CLI takes what Python takes: --kn/--kt per contact (R1, L1, L2), --x-d, --contacts-from FILE
(explicit flags override it), with the library's checks and one error line naming the flag."""

import json

import numpy as np
import pytest

import jaxdamp as jd
from helpers import one_error_line, run_cli, strict_json

KN, KT = (2e4, 2e4, 1.8e4), (4000.0, 3500.0, 3000.0)


def _python_numbers(shape, mu, contacts):
    return jd.five_numbers(jd.base_cycle(shape, mu, contacts))


def test_per_contact_stiffness_and_x_d_match_python(capsys):
    shape = jd.family_shape("60sym")._replace(x_d=0.55)
    code, out, _ = run_cli(capsys, "cycle", "--shape", "60sym", "--mu", "0.5", "--kn", "2e4,2e4,1.8e4",
                           "--kt", "4000,3500,3000", "--x-d", "0.55", "--json")
    d = strict_json(out)
    ref = _python_numbers(shape, 0.5, jd.Contacts(np.array(KN), np.array(KT)))
    assert code == 0 and d["status"] == "ok"
    assert d["inputs"]["contacts"]["kn_n_per_mm"] == dict(zip(("R1", "L1", "L2"), KN))
    assert d["inputs"]["shape"]["x_d_over_h"] == 0.55
    assert d["psi_bc_mrad"] == pytest.approx(float(ref.psi_bc), rel=1e-12)
    assert d["k_im_bc"] == pytest.approx(float(ref.k_im_bc), rel=1e-12)
    # one value means all three contacts: the same numbers as three equal values
    _, one, _ = run_cli(capsys, "cycle", "--shape", "60sym", "--mu", "0.5", "--kn", "2e4", "--json")
    _, three, _ = run_cli(capsys, "cycle", "--shape", "60sym", "--mu", "0.5", "--kn", "2e4,2e4,2e4", "--json")
    assert strict_json(one)["k_im_bc"] == strict_json(three)["k_im_bc"]


def _contacts_file(tmp_path, **contacts):
    f = tmp_path / "contacts.json"
    f.write_text(json.dumps({"contacts": contacts}))
    return f


def test_contacts_from_file_and_flags_override(tmp_path, capsys):
    f = _contacts_file(tmp_path, kn_n_per_mm=list(KN), kt_n_per_mm=list(KT), mu=[0.4, 0.4, 0.4])
    code, out, _ = run_cli(capsys, "cycle", "--shape", "60sym", "--contacts-from", f, "--json")
    d = strict_json(out)
    ref = _python_numbers(jd.family_shape("60sym"), 0.4, jd.Contacts(np.array(KN), np.array(KT)))
    assert code == 0 and d["inputs"]["mu"] == 0.4
    assert d["k_re_bc"] == pytest.approx(float(ref.k_re_bc), rel=1e-12)
    code, out, _ = run_cli(capsys, "cycle", "--shape", "60sym", "--contacts-from", f, "--kt", "3000",
                           "--mu", "0.6", "--json")
    d = strict_json(out)
    assert code == 0 and d["inputs"]["mu"] == 0.6 and d["inputs"]["contacts"]["kt_n_per_mm"] == 3000.0
    assert d["inputs"]["contacts"]["kn_n_per_mm"] == dict(zip(("R1", "L1", "L2"), KN))


@pytest.mark.slow  # 13 worker-s (run of 2026-11-25)
@pytest.mark.parametrize("command", ["grad", "amplitude"])
def test_every_design_command_takes_the_contact_flags(tmp_path, capsys, command):
    extra = ["--psi-a", "3"] if command == "amplitude" else []
    code, out, _ = run_cli(capsys, command, "--shape", "60sym", "--mu", "0.5", "--kn", "2e4,2e4,1.8e4",
                           "--x-d", "0.5", *extra, "--json")
    assert code == 0 and strict_json(out)["status"] == "ok"


@pytest.mark.parametrize("content, needle", [
    ("{not json", "is not a contacts file"),
    ('{"kn": 1}', 'no "contacts" object'),
    ('{"contacts": {"kn_n_per_mm": [1, 2]}}', "three numbers"),
    ('{"contacts": {"mu": [0.3, 0.5, 0.5]}}', "per-contact mu"),
])
def test_bad_contacts_file_is_one_line(tmp_path, capsys, content, needle):
    f = tmp_path / "c.json"
    f.write_text(content)
    code, _, err = run_cli(capsys, "cycle", "--shape", "60sym", "--mu", "0.5", "--contacts-from", f)
    line = one_error_line(err)
    assert code == 2 and "--contacts-from" in line and needle in line, line


def test_missing_contacts_file_and_bad_values(tmp_path, capsys):
    code, _, err = run_cli(capsys, "cycle", "--shape", "60sym", "--mu", "0.5", "--contacts-from", tmp_path / "no")
    assert code == 2 and "--contacts-from" in one_error_line(err) and "cannot be read" in err
    f = _contacts_file(tmp_path, kn_n_per_mm=[2e4, -1, 2e4])
    code, _, err = run_cli(capsys, "cycle", "--shape", "60sym", "--mu", "0.5", "--contacts-from", f)
    assert code == 2 and "--kn must be in (0, inf) N/mm; got -1" in one_error_line(err)
    code, _, err = run_cli(capsys, "cycle", "--shape", "60sym", "--mu", "0.5", "--kn", "2e4,nan,2e4")
    assert code == 2 and "--kn must be a finite number" in one_error_line(err)


@pytest.mark.parametrize("command", [["sweep", "--out", "OUT"], ["optimize"]])
def test_shared_pair_commands_refuse_three_values(tmp_path, capsys, command):
    argv = [str(tmp_path / "o") if a == "OUT" else a for a in command]
    code, _, err = run_cli(capsys, *argv, "--kn", "2e4,2e4,1.8e4")
    line = one_error_line(err)
    assert code == 2 and "--kn takes one value here" in line and "(20000, 20000, 18000)" in line
    assert not (tmp_path / "o").exists()
