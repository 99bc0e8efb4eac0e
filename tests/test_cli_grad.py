"""`jaxdamp grad`: the JSON contract equals the library's Jacobian; text; liftoff; errors."""

import numpy as np
import pytest

import jaxdamp as jd
from jaxdamp import gradients as G

from helpers import one_error_line, run_cli, strict_json

P = G.PARAMETERS


def test_cli_grad_json_contract(capsys):
    code, out, _ = run_cli(capsys, "grad", "--shape", "74R", "--mu", "0.5", "--kn", "17900", "--kt", "3600",
                           "--json")
    assert code == 0
    d = strict_json(out)
    for key in ("psi_bc_mrad", "k_im_bc", "k_re_bc"):
        # Derivatives with respect to every leaf of the Design: the shape, mu, contacts and load.
        assert set(d[key]) == set(P) | {"F_D", "q_star", "r_sin_beta"}
        assert all(np.isfinite(v) for v in d[key].values())
    jac = G.five_numbers_jacobian(jd.family_shape("74R"), 0.5, jd.Contacts(17900.0, 3600.0))
    assert d["psi_bc_mrad"]["theta_l"] == pytest.approx(float(jac.d.psi_bc.shape.theta_l), rel=1e-12)
    assert d["k_im_bc"]["kt"] == pytest.approx(float(jac.d.k_im_bc.contacts.kt), rel=1e-12)
    assert d["status"] == "ok" and not {"converged", "liftoff", "failed"} & set(d)
    assert d["inputs"]["contacts"] == {"kn_n_per_mm": 17900.0, "kt_n_per_mm": 3600.0}


def test_cli_grad_text_and_errors(capsys):
    code, out, _ = run_cli(capsys, "grad", "--theta-l", "60", "--theta-r", "60", "--br", "0.14", "--mu", "0.3",
                           "--psi-a", "2.5")
    assert code == 0
    assert "psi_bc_mrad" in out and "k_im_at_psi_a" in out and "theta_l" in out
    code, _, err = run_cli(capsys, "grad", "--shape", "60sym", "--mu", "0")
    assert code == 2 and "mu" in one_error_line(err)
    code, _, err = run_cli(capsys, "grad", "--shape", "60sym", "--mu", "0.5", "--psi-a", "-1")
    assert code == 2 and "--psi-a" in one_error_line(err)


def test_cli_grad_liftoff_is_null(capsys):
    code, out, _ = run_cli(capsys, "grad", "--shape", "74L", "--mu", "0.7", "--json")
    assert code == 0
    d = strict_json(out)
    assert d["status"] == "liftoff" and d["values"]["psi_bc_mrad"] is None
    assert set(d["psi_bc_mrad"].values()) == {None}
    code, out, _ = run_cli(capsys, "grad", "--shape", "74L", "--mu", "0.7")
    assert code == 0 and "liftoff" in out.splitlines()[0]
