"""The examples run, and what they show is the physics they claim."""

import os

# Before matplotlib is first imported anywhere in this process: no display needed.
os.environ["MPLBACKEND"] = "Agg"

import json
import re
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO

EXAMPLES = REPO / "python" / "examples"


@pytest.fixture(scope="module")
def lesson():
    """The notebook's namespace after running its code cells in order, as a kernel would."""
    import matplotlib.pyplot as plt

    path = EXAMPLES / "fourier_lesson.ipynb"
    notebook = json.loads(path.read_text(encoding="utf-8"))
    assert notebook["nbformat"] == 4
    namespace = {"__name__": "__main__"}
    figures = 0
    for index, cell in enumerate(notebook["cells"]):
        assert "outputs" not in cell or cell["outputs"] == [], f"cell {index} has stored outputs"
        if cell["cell_type"] != "code":
            continue
        source = "".join(cell["source"])
        exec(compile(source, f"{path.name}, cell {index} ({cell.get('id')})", "exec"), namespace)
        figures += len(plt.get_fignums())
        plt.close("all")
    namespace["_figures"] = figures
    return namespace


def test_the_lesson_draws_a_figure_per_step(lesson):
    assert lesson["_figures"] >= 6


def test_the_slit_is_sinc_squared(lesson):
    theory = lesson["slit_theory"]
    assert theory.theory == "single slit"
    assert theory.deviation < 0.01
    assert theory.mtf is not None and theory.mtf.deviation < 0.02
    # Fringes every λf/a: 0.61 µm × 10 mm / 216 µm.
    assert lesson["slit_width_um"] == pytest.approx(216.0)
    assert lesson["fringe_um"] == pytest.approx(0.61 * 10_000 / 216, rel=1e-3)
    # Past the cutoff a/(λf) the MTF across the slit is (close to) zero.
    mtf = theory.mtf
    beyond = mtf.freq_cyc_per_px > 1.1 * lesson["cutoff_cyc_per_px"]
    assert beyond.any() and np.abs(mtf.simulated[beyond]).max() < 0.01


def test_the_grating_has_its_orders_and_misses_every_fifth(lesson):
    theory, orders = lesson["grating_theory"], lesson["orders"]
    assert lesson["duty"] == pytest.approx(0.2)
    assert theory.deviation < 0.05
    assert np.allclose(theory.x_um, orders * lesson["order_spacing_um"], atol=0.01)
    light = dict(zip(orders.tolist(), theory.simulated))
    assert light[0] == pytest.approx(0.2, abs=0.01)  # a/P of the light in order 0
    assert light[1] == pytest.approx(0.2 * np.sinc(0.2) ** 2, abs=0.01)
    assert sorted(set(lesson["missing"].tolist())) == [-10, -5, 5, 10]
    for m in (-10, -5, 5, 10):
        assert light[m] < 1e-3
    # The radially-minimum MTF has fallen to zero past the first band of zeros.
    a = lesson["grating_analysis"]
    past = a.freq_cyc_per_px > 2 * lesson["first_zero_cyc_per_px"]
    assert a.radial_min[:, past].max() < 0.01


def test_the_toled_orders_scale_with_the_wavelength(lesson):
    a = lesson["toled_analysis"]
    expected_um = a.wavelength_nm * 1e-3 * 10_000 / lesson["toled_period_um"]
    assert np.allclose(lesson["toled_spacing_um"], expected_um, rtol=0.01)
    assert all(t.deviation < 0.05 for t in lesson["toled_theories"])
    assert a.ltr == pytest.approx(5 / 21, abs=0.005)


def test_the_random_tiling_trades_orders_for_a_halo_that_fills_the_mtf(lesson):
    # The notebook's own coherent fraction (from the mean tile) is what udc.theory reports.
    note = lesson["random_theory"].note
    reported = float(re.search(r"([\d.]+) % of the light", note).group(1)) / 100
    assert lesson["coherent_fraction"] == pytest.approx(reported, abs=0.001)
    assert lesson["coherent_fraction"] == pytest.approx(0.65, abs=0.01)

    periodic, random = lesson["l_periodic_analysis"], lesson["l_random_analysis"]
    assert random.ltr == pytest.approx(periodic.ltr, rel=0.01)  # same opening, same light
    assert (random.auc > 2 * periodic.auc).all()
    zero_share = lesson["zero_share"]
    assert (zero_share(random) == 0).all() and (zero_share(periodic) > 0.3).all()

    thesis, thesis_periodic = lesson["thesis_analysis"], lesson["thesis_periodic_analysis"]
    assert (thesis.auc > thesis_periodic.auc).all()


def test_the_summary_covers_every_step(lesson):
    analyses = dict(lesson["analyses"])
    assert {"fourier-slit", "fourier-grating", "toled-150dpi", "fourier-periodic",
            "fourier-random", "l2inv-random", "open-aperture"} <= set(analyses)
    # The bare lens passes all the light and keeps the most detail.
    bare = analyses.pop("open-aperture")
    assert bare.ltr == pytest.approx(1.0)
    assert all(bare.auc.mean() > a.auc.mean() and a.ltr < 1 for a in analyses.values())


def test_the_design_study_runs_and_plots(tmp_path):
    out = tmp_path / "x.png"
    # cwd=tmp_path: from the repository's python/ the source package (without its native
    # module) would shadow the staged one that conftest put on PYTHONPATH.
    run = subprocess.run(
        [sys.executable, str(EXAMPLES / "design_study.py"), "--seeds", "3", "--quick",
         "--out", str(out)],
        cwd=tmp_path, env=os.environ.copy(), capture_output=True, text=True, timeout=300,
    )
    assert run.returncode == 0, run.stderr
    assert "AUC (cycles/pixel)" in run.stdout and "LTR (%)" in run.stdout
    rows = [line.split() for line in run.stdout.splitlines()
            if re.match(r"(repeat|random-4|random-d4) +(-|\d+) ", line)]
    assert [row[:2] for row in rows] == [["repeat", "-"], ["random-4", "0"], ["random-4", "1"],
                                         ["random-4", "2"]]
    periodic_auc = float(rows[0][2])
    assert all(float(row[2]) > periodic_auc for row in rows[1:])
    assert out.read_bytes().startswith(b"\x89PNG\r\n\x1a\n")


def test_the_design_study_rejects_an_unknown_preset(tmp_path):
    run = subprocess.run(
        [sys.executable, str(EXAMPLES / "design_study.py"), "--preset", "no-such-design"],
        cwd=tmp_path, env=os.environ.copy(), capture_output=True, text=True, timeout=60,
    )
    assert run.returncode == 2 and "no-such-design" in run.stderr
