"""Atomic writes (jaxdamp.paper.files): an interrupted write leaves no half-written file beside
complete ones, and a previous version of the target stays whole."""

import ast
import os
from pathlib import Path

import matplotlib
import numpy as np
import pytest

from jaxdamp.paper.files import atomic_file, save_figure, write_bytes, write_text
from helpers import one_error_line, run_cli

matplotlib.use("Agg")
ROOT = Path(__file__).resolve().parents[1]


class Interrupted(BaseException):
    """Like KeyboardInterrupt: not an Exception, so nothing on the way may swallow it."""


def test_complete_writes(tmp_path):
    write_text(tmp_path / "a.json", '{"a": 1}')
    write_bytes(tmp_path / "b.bin", b"\x00\x01")
    with atomic_file(tmp_path / "c.npz", "wb") as f:
        np.savez_compressed(f, x=np.arange(3.0))
    assert (tmp_path / "a.json").read_text() == '{"a": 1}' and (tmp_path / "b.bin").read_bytes() == b"\x00\x01"
    assert np.load(tmp_path / "c.npz")["x"].tolist() == [0.0, 1.0, 2.0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.json", "b.bin", "c.npz"]  # no temporary left
    mode = (tmp_path / "a.json").stat().st_mode & 0o777
    umask = os.umask(0)
    os.umask(umask)
    assert mode == 0o666 & ~umask  # the permissions open() gives, not mkstemp's 0600


def test_interrupted_write_leaves_nothing_half_written(tmp_path):
    write_text(tmp_path / "study.json", '{"complete": true}')
    with pytest.raises(Interrupted):
        with atomic_file(tmp_path / "study.json") as f:
            f.write('{"compl')
            raise Interrupted
    with pytest.raises(Interrupted):
        with atomic_file(tmp_path / "new.csv") as f:
            f.write("shape,mu\n60sym,")
            raise Interrupted
    assert sorted(p.name for p in tmp_path.iterdir()) == ["study.json"]
    assert (tmp_path / "study.json").read_text() == '{"complete": true}'


def test_interrupted_figure(tmp_path, monkeypatch):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    save_figure(fig, tmp_path / "complete.png", dpi=50)
    assert (tmp_path / "complete.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    def half(self, f, **kw):  # writes part of the image, then the run is stopped
        f.write(b"\x89PNG\r\n")
        raise Interrupted

    # the PNG writer both ways of saving end in (save_figure's one draw, and savefig)
    monkeypatch.setattr(FigureCanvasAgg, "print_png", half)
    for kw in ({}, {"dpi": 40}, {"metadata": {"Title": "x"}}):
        with pytest.raises(Interrupted):
            save_figure(fig, tmp_path / "half.png", **kw)
    monkeypatch.undo()
    plt.close(fig)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["complete.png"]


def test_a_png_is_drawn_once_as_savefig_would_save_it(tmp_path, monkeypatch):
    """save_figure's PNG (one draw by the Agg canvas) is savefig's, pixel for pixel, for a
    constrained layout with a title, a legend, a colour bar and a second x axis on top, at the
    figure's dpi and another; the figure keeps its own dpi."""
    import matplotlib.pyplot as plt

    def build():
        fig, (a, b) = plt.subplots(1, 2, figsize=(6, 3), dpi=80, layout="constrained")
        a.plot([0, 1, 2], [1, 0, 2], label="a line")
        a.legend()
        a.set_title("a title")
        a.secondary_xaxis("top").set_xlabel("on top")
        fig.colorbar(b.imshow(np.arange(12.0).reshape(3, 4)), ax=b, label="colour")
        fig.suptitle("both")
        return fig

    draws = []
    real_draw = matplotlib.figure.Figure.draw
    monkeypatch.setattr(matplotlib.figure.Figure, "draw",
                        lambda self, r: draws.append(1) or real_draw(self, r))
    for kw in ({}, {"dpi": 110}):
        fig = build()
        canvas = fig.canvas
        save_figure(fig, tmp_path / "once.png", **kw)
        assert fig.get_dpi() == 80 and fig.canvas is canvas
        n_once, draws[:] = len(draws), []
        fig2 = build()
        fig2.savefig(tmp_path / "savefig.png", **kw)
        assert (n_once, len(draws)) == (1, 2)
        draws[:] = []
        once, ref = plt.imread(tmp_path / "once.png"), plt.imread(tmp_path / "savefig.png")
        assert once.shape == ref.shape and np.array_equal(once, ref)
        plt.close(fig)
        plt.close(fig2)


def test_interrupted_cli_figure(tmp_path, capsys, monkeypatch):
    """`jaxdamp section` stopped while its PNG is written leaves no file."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    def half(self, f, **kw):
        f.write(b"\x89PNG")
        raise Interrupted

    monkeypatch.setattr(FigureCanvasAgg, "print_png", half)
    with pytest.raises(Interrupted):
        run_cli(capsys, "section", "--shape", "60sym", "--mu", "0.5", "--out", tmp_path / "s.png")
    assert list(tmp_path.iterdir()) == []


WRITERS = ("savefig", "write_text", "write_bytes", "savez", "savez_compressed", "open")


@pytest.mark.parametrize("folder", ["jaxdamp/cli", "jaxdamp/paper", "jaxdamp/plotting", "optimize"])
def test_every_writer_goes_through_the_helper(folder):
    """No module but jaxdamp/paper/files.py writes a file directly: every savefig, write_text,
    savez and open() for writing is inside jaxdamp.paper.files (a writer may hand it a file
    object, as np.savez_compressed(f, ...) in `with atomic_file(...) as f`)."""
    found = []
    for path in sorted((ROOT / folder).rglob("*.py")):
        if path.name == "files.py" and path.parent.name == "paper":
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, ast.Call):
                continue
            name = getattr(node.func, "attr", getattr(node.func, "id", ""))
            if name not in WRITERS:
                continue
            if name == "open":
                mode = node.args[1] if len(node.args) > 1 else next(
                    (k.value for k in node.keywords if k.arg == "mode"), None)
                if not (isinstance(mode, ast.Constant) and any(c in str(mode.value) for c in "wax")):
                    continue
            if name in ("write_text", "write_bytes") and (isinstance(node.func, ast.Name) or (
                    isinstance(node.func.value, ast.Name) and node.func.value.id == "C")):
                continue  # the helper itself (jaxdamp.cli.common re-exports it as C.write_text)
            if name in ("savez", "savez_compressed") and node.args and isinstance(node.args[0], ast.Name) \
                    and node.args[0].id == "f":
                continue  # a file object from atomic_file
            found.append(f"{path.relative_to(ROOT)}:{node.lineno} {name}")
    assert found == []
