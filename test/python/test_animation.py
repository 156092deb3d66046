"""kane_sim.animate and the plots from Python; the example script runs headless and writes its
GIF and figures."""
import os
import re
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

import kane_sim
from conftest import config_path

EXAMPLE = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "python",
                       "crank_animation.py")


def test_the_example_writes_its_animation_and_figures(tmp_path):
    r = subprocess.run([sys.executable, EXAMPLE, str(tmp_path)], capture_output=True, text=True,
                       timeout=240)
    assert r.returncode == 0, r.stderr
    gif = Image.open(tmp_path / "crank.gif")
    assert gif.n_frames == 41  # 2 s at 20 frames per second, both ends
    assert gif.size == (400, 480)
    # frames differ: the crank moves
    gif.seek(0)
    first = np.asarray(gif.convert("RGB"), dtype=int)
    gif.seek(20)
    middle = np.asarray(gif.convert("RGB"), dtype=int)
    assert np.abs(first - middle).sum() > 0
    for png in ("swing_up.png", "reactions_one_turn.png"):
        assert os.path.getsize(tmp_path / png) > 10000, png
    assert "one turn: |pin O| up to" in r.stdout


def test_the_notebook_runs_and_shows_its_plots_and_animation(tmp_path):
    """examples/python/kane_sim_tour.ipynb executed by nbconvert, as Jupyter would."""
    notebook = os.path.join(os.path.dirname(EXAMPLE), "kane_sim_tour.ipynb")
    out = tmp_path / "executed.ipynb"
    r = subprocess.run([sys.executable, "-m", "nbconvert", "--to", "notebook", "--execute",
                        notebook, "--output", str(out),
                        "--ExecutePreprocessor.timeout=180"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-3000:]
    import nbformat
    cells = [c for c in nbformat.read(str(out), 4).cells if c.cell_type == "code"]
    kinds = [set(k for o in c.outputs for k in o.get("data", {})) for c in cells]
    assert all(o.output_type != "error" for c in cells for o in c.outputs)
    assert "image/png" in kinds[1] and "image/png" in kinds[4]  # the run's and reactions' plots
    assert "text/html" in kinds[2]  # the animation's player


def test_animate_draws_the_models_geometry():
    sim = kane_sim.Simulator(config_path())
    r = sim.run(0.2, torque=1.0, output_rate=100)
    anim = kane_sim.animate(r, fps=10)
    anim._draw_next_frame(2, blit=False)  # t = 0.2 s
    rod1 = anim._fig.axes[0].lines[2]  # rail and pivot first
    L = sim.config["mechanism.rod_half_length"]
    q1 = r["q1"][-1]
    # rod 1 from O to A = 2L (cos q1, sin q1) in frame (0), drawn as (y, -x)
    np.testing.assert_allclose(rod1.get_xdata(), [0, 2 * L * np.sin(q1)], atol=1e-12)
    np.testing.assert_allclose(rod1.get_ydata(), [0, -2 * L * np.cos(q1)], atol=1e-12)


def test_animate_refuses_what_it_cannot_draw():
    r = kane_sim.Simulator(config_path()).run(0.1, output_rate=100)
    with pytest.raises(ValueError, match="fps"):
        kane_sim.animate(r, fps=0)
    with pytest.raises(ValueError, match="rod_half_length"):
        kane_sim.animate({"t": r.t, "q1": r["q1"], "q2": r["q2"]})
    with pytest.raises(ValueError, match="at least 2"):
        kane_sim.animate({"t": [0.0], "q1": [0.0], "q2": [1.0]}, rod_half_length=0.25)
    with pytest.raises(ValueError, match="kind"):
        kane_sim.plot_result(r, kind="energy")


ROOT = os.path.join(os.path.dirname(EXAMPLE), "..", "..")


def documentation():
    """(path relative to the checkout, text) of README.md and every doc/**/*.md."""
    pages = ["README.md"]
    for folder, dirs, names in os.walk(os.path.join(ROOT, "doc")):
        dirs.sort()
        pages += [os.path.relpath(os.path.join(folder, n), ROOT) for n in sorted(names)
                  if n.endswith(".md")]
    return [(page, open(os.path.join(ROOT, page), encoding="utf-8").read()) for page in pages]


def test_the_python_examples_of_the_docs_run_as_written(tmp_path):
    """Every ```python block of README.md and doc/**/*.md runs; the Python guide's makes its GIF."""
    blocks = [(page, i, block.split("```", 1)[0]) for page, text in documentation()
              for i, block in enumerate(text.split("```python\n")[1:])]
    assert any(page == os.path.join("doc", "guide", "python.md") for page, _, _ in blocks), \
        "no ```python block in doc/guide/python.md"
    for page, i, block in blocks:
        script = tmp_path / ("example_%d.py" % i)
        script.write_text(block)
        r = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True,
                           text=True, timeout=240)
        assert r.returncode == 0, "%s, python block %d: %s" % (page, i + 1, r.stderr)
    assert Image.open(tmp_path / "swing.gif").n_frames > 10


def test_every_figure_of_the_docs_has_its_command_and_it_runs(tmp_path):
    """Each doc/*.png that README.md or a page of doc/ shows has the command that makes it
    beside it, on that page; the Python ones run here into a scratch folder (the node's figures
    need a master: their commands are the launch tests' own)."""
    commands = {
        "doc/power_flow.png": "python3 doc/power_flow.py",
        "doc/reactions_one_turn.png": "python3 examples/python/crank_animation.py doc",
        "doc/linear_response.png": "python3 doc/linear_response.py BUILD_DIR",
        "doc/sensors_vs_ideal.png": "rosrun kane_sim plot_bag noisy.bag --compare",
    }
    shown = {}  # figure -> [(page, text, position of its link)]
    for page, text in documentation():
        for m in re.finditer(r"!\[[^\]]*\]\(([^)\s]+\.png)\)", text):
            figure = os.path.normpath(os.path.join(os.path.dirname(page), m.group(1)))
            shown.setdefault(figure.replace(os.sep, "/"), []).append((page, text, m.start()))
    for figure, command in commands.items():
        assert figure in shown, "%s is shown nowhere in README.md or doc/" % figure
        for page, text, at in shown[figure]:
            near = text[max(0, at - 1500):at + 1500]
            assert command in near, "%s in %s: no '%s' beside it" % (figure, page, command)
    out = tmp_path / "power_flow.png"
    r = subprocess.run([sys.executable, os.path.join(ROOT, "doc", "power_flow.py"), str(out)],
                       capture_output=True, text=True, timeout=240)
    assert r.returncode == 0, r.stderr
    assert Image.open(out).size[0] > 800
