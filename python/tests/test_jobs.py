"""`phase`, `sensor` and `sweep`: the jobs the commands run, in-process, with the commands'
parameters, messages and JSON."""

import json

import numpy as np
import pytest

import udc_studio as udc
from conftest import REPO, assert_ctrl_c_stops, run_cli

HDR = REPO / "assets" / "hdr" / "Desk_322x437.exr"


def without_time(value):
    # The time, and the build the command line names in what it prints (`tool_version`).
    if isinstance(value, dict):
        return {
            k: without_time(v) for k, v in value.items() if k not in ("elapsed_ms", "tool_version")
        }
    if isinstance(value, list):
        return [without_time(v) for v in value]
    return value


def test_phase_psf_is_the_clis(cli):
    ours = udc.phase.psf(preview=True, angle_deg=5.0)
    theirs = run_cli(cli, "phase", "psf", "--preview", "--angle-deg", "5.0", "--json")
    assert theirs.returncode == 0, theirs.stderr
    assert without_time(ours) == without_time(json.loads(theirs.stdout))
    # The double MLA gathers more light than the bare T-OLED (thesis §4.4).
    assert all(c["energy_vs_toled"] > 1.0 for c in ours["channels"])
    assert np.asarray(ours["channels"][0]["psf"]).ndim == 1


@pytest.mark.parametrize(
    "command, call",
    [
        (["phase", "invertibility", "--preview"], lambda: udc.phase.invertibility(preview=True)),
        (["phase", "optimize", "--preview"], None),
    ],
)
def test_the_phase_matrix_and_allocation_are_the_clis(cli, tmp_path, command, call):
    if call is None:
        # optimize writes the optimized design: each run its own file.
        command = command + ["--out", str(tmp_path / "cli.json")]
        call = lambda: udc.phase.optimize(preview=np.True_, out=tmp_path / "py.json")  # noqa: E731
    theirs = run_cli(cli, *command, "--json")
    assert theirs.returncode == 0, theirs.stderr
    assert without_time(call()) == without_time(json.loads(theirs.stdout))


def test_numpy_scalars_are_parameter_values(cli):
    ours = udc.phase.psf(preview=np.True_, angle_deg=np.float64(5.0))
    assert without_time(ours) == without_time(udc.phase.psf(preview=True, angle_deg=5.0))


def test_sensor_simulate_is_the_clis_and_picks_a_strategy(cli):
    ours = udc.sensor.simulate(HDR, max_side_px=128)
    theirs = run_cli(cli, "sensor", "--hdr", str(HDR), "--max-side-px", "128", "--json")
    assert without_time(ours) == without_time(json.loads(theirs.stdout))
    one = udc.sensor.simulate(HDR, strategy="vary-gain/vary-bin", max_side_px=128)
    assert [s["name"] for s in one["strategies"]] == ["vary-gain/vary-bin"]
    every = {s["name"]: s for s in ours["strategies"]}
    assert one["strategies"][0] == every["vary-gain/vary-bin"]


def test_bad_parameters_raise_one_line_messages_naming_them(tmp_path):
    with pytest.raises(ValueError, match="--photons NaN: must be 10"):
        udc.phase.restore(photons=float("nan"))
    for bad in (float("nan"), float("inf"), -1.0):
        with pytest.raises(ValueError, match=r"--denoise-sigma2 .*: the noise variance must be a finite number > 0"):
            udc.phase.restore(preview=True, photons=650, denoise_sigma2=bad)
    with pytest.raises(ValueError, match="unknown parameter `colour`"):
        udc.phase.psf(colour="red")
    with pytest.raises(ValueError, match="parameter `angle-deg`"):
        udc.phase.psf(angle_deg="steep")
    with pytest.raises(ValueError, match="relay.*lenslet-period"):
        udc.phase.psf(relay="sideways")
    with pytest.raises(ValueError, match="strategy: unknown"):
        udc.sensor.simulate(HDR, strategy="free-lunch", max_side_px=64)
    with pytest.raises(OSError, match="missing.exr"):
        udc.sensor.simulate(tmp_path / "missing.exr")


def test_a_phase_operator_on_the_gpu_restores_as_the_cpus(on_gpu):
    """A λ0 plan's operator through the Bloch relay on any adapter (a software one included);
    V under the lenslet period has no step on the device, and says so."""
    kw = dict(preview=True, peaks=True, lambda0="uniform", relay="wrapped-display",
              scene_px=16, photons=[1000.0], denoise="none")
    cpu = udc.phase.restore(**kw)
    gpu = on_gpu(udc.phase.restore, **kw)
    assert "backend" not in cpu and gpu["backend"]["adapter"]
    assert gpu["backend"]["device_transforms"] > 0
    assert gpu["ltr"] == pytest.approx(cpu["ltr"], rel=1e-5)
    v = on_gpu(udc.phase.invertibility, preview=True)
    assert v["backend"]["device_transforms"] == 0
    assert v["v"] == udc.phase.invertibility(preview=True)["v"]
    assert gpu["runs"][0]["psnr_db"] == pytest.approx(cpu["runs"][0]["psnr_db"], abs=0.01)


def test_a_sweep_returns_its_table_and_resumes(tmp_path):
    spec = tmp_path / "seeds.toml"
    spec.write_text(
        'name = "seeds"\njob = "analyze"\n'
        'base = { preset = "l2inv-random", preview = true }\n'
        'metrics = ["auc_radial_min_mean", "ltr"]\n'
        '[[axis]]\nparam = "seed"\nrange = { start = 0, stop = 2 }\n'
    )
    out = tmp_path / "out"
    table = udc.sweep(spec, out)
    # Rows are written as points finish (in parallel): any order.
    seeds = list(np.asarray(table["seed"], dtype=float))
    assert sorted(seeds) == [0.0, 1.0, 2.0]
    auc = np.asarray(table["auc_radial_min_mean"], dtype=float)
    for seed, value in zip(seeds, auc):
        design = udc.Design.from_preset("l2inv-random").with_(seed=int(seed))
        assert value == pytest.approx(udc.analyze(design, quality="preview").auc.mean(), abs=1e-6)
    # A second run finds every point done and computes nothing.
    summary = udc._native.sweep(str(spec), str(out), None)
    assert (summary["computed"], summary["skipped"], summary["complete"]) == (0, 3, True)
    again = udc.sweep(spec, out)
    assert sorted(np.asarray(again["seed"], dtype=float)) == sorted(seeds)


def test_ctrl_c_cancels_a_phase_command(tmp_path):
    # A capture through the whole display takes about 15 s on 2 cores; cancelled, it stops at
    # its next direction.
    assert_ctrl_c_stops('udc.phase.restore(relay="whole-display")', tmp_path, within_s=3.0)


def test_a_sweeps_figures_are_its_plots_as_arrays(tmp_path):
    spec = tmp_path / "seeds.toml"
    spec.write_text(
        'name = "tilings"\njob = "analyze"\n'
        'base = { preset = "toled-150dpi", preview = true }\n'
        'metrics = ["auc_radial_min_mean", "ltr"]\n'
        '[[axis]]\nparam = "tiling"\nvalues = ["repeat", "random-4"]\n'
        '[[axis]]\nparam = "seed"\nrange = { start = 0, stop = 1 }\n'
    )
    out = tmp_path / "out"
    table = udc.sweep(spec, out)
    figures = udc.sweep_figures(out)
    # The default plots, as the CLI drew them: the metric against the tiling over seeds, and
    # the AUC-LTR Pareto front.
    assert [f["title"] for f in figures] == [
        "tilings: auc_radial_min_mean vs tiling",
        "tilings: auc_radial_min_mean vs ltr",
    ]
    assert sorted(p.name for p in (out / "plots").glob("*.png")) == sorted(
        ["auc_radial_min_mean-vs-tiling.png", "pareto-auc_radial_min_mean-ltr.png"]
    )
    first = figures[0]
    assert first["x"]["categories"] == ["repeat", "random-4"]
    (line,) = first["series"]
    assert line["points"].shape == (2, 2) and line["band"].shape == (2, 3)
    # Each point is the mean over the seeds of that tiling, its band ± the sample SD.
    auc = np.asarray(table["auc_radial_min_mean"], dtype=float)
    tilings = list(table["tiling"])
    for (x, y), (_, lo, hi) in zip(line["points"], line["band"]):
        values = [a for a, t in zip(auc, tilings) if t == first["x"]["categories"][int(x)]]
        sd = np.std(values, ddof=1)
        assert y == pytest.approx(np.mean(values))
        assert lo == pytest.approx(np.mean(values) - sd) and hi == pytest.approx(np.mean(values) + sd)
    pareto = figures[1]
    assert [s["name"] for s in pareto["series"]] == ["rows", "Pareto front"]
    assert pareto["series"][0]["points"].shape == (4, 2)
    with pytest.raises(OSError):
        udc.sweep_figures(tmp_path / "missing")


def test_the_optimal_pitch_figures_are_the_studios_fig_5_3():
    contrast, best = udc.sensor.pitch_figures(light_e_per_um2=50.0, pitch_um=1.0)
    assert contrast["x"]["unit"] == "cycles/µm"
    nyquist, cutoff = (a["x"] for a in contrast["annotations"])
    assert nyquist == pytest.approx(0.5)
    # Below the cutoff the contrast clears the noise threshold, above it it does not.
    c, thr = (np.asarray(s["points"]) for s in contrast["series"])
    below, above = c[:, 0] < 0.9 * cutoff, (c[:, 0] > 1.1 * cutoff) & (c[:, 0] < 1.0)
    assert np.all(c[below, 1] > thr[below, 1]) and np.all(c[above, 1] < thr[above, 1])
    # More light, a finer optimal pitch.
    pitch = np.asarray(best["series"][0]["points"])
    assert pitch[0, 1] > pitch[-1, 1]
    with pytest.raises(ValueError, match="sensor: unknown"):
        udc.sensor.pitch_figures(sensor="film")
    with pytest.raises(ValueError, match="pitch_um"):
        udc.sensor.pitch_figures(pitch_um=float("nan"))


def test_none_and_false_leave_a_parameter_at_its_default():
    # `height_step_um` is a number or nothing; `False` and `None` both mean nothing, as a switch
    # off does in a sweep spec.
    base = udc.phase.psf(preview=True)
    assert without_time(udc.phase.psf(preview=True, height_step_um=None, unfolded=False)) == (
        without_time(base)
    )
    assert without_time(udc.phase.psf(preview=np.True_, height_step_um=False)) == without_time(base)


def test_view_figures_are_the_analysis_on_the_sensor_grid_with_its_landmarks():
    design = "toled-150dpi"
    a = udc.analyze(design, quality="preview")
    figs = udc.view_figures(design, quality="preview", orders=True)
    n = len(a.channels)
    assert len(figs) == 3 * n + 2, "PSF, log-PSF and 2-D MTF a channel, RGB, MTF curves"
    log_psf = figs[1]
    img = log_psf["images"][0]
    # The image is the analysis's PSF, row 0 at the top, on the sensor window.
    np.testing.assert_array_equal(img["values"], a.psf[0])
    rows, cols = img["values"].shape
    left, right, bottom, top = img["extent"]
    assert right - left == pytest.approx(cols * a.sensor_pixel_um)
    assert top - bottom == pytest.approx(rows * a.sensor_pixel_um)
    assert img["scale"]["kind"] == "log" and img["scale"]["floor_decades"] == 6.0
    assert img["colormap"] == "inferno"
    assert img["paint"] == "mapped" and "categories" not in img
    assert img["rgb"].shape == (rows, cols, 3) and img["rgb"].dtype == np.uint8
    # The brightest colour is at the peak.
    r, c = np.unravel_index(np.argmax(img["values"]), img["values"].shape)
    assert img["rgb"][r, c].sum() == img["rgb"].sum(axis=2).max()
    kinds = {note["kind"] for note in log_psf["annotations"]}
    assert kinds == {"ring", "lattice"}
    ring = next(note for note in log_psf["annotations"] if note["kind"] == "ring")
    f_number = udc.Design.from_preset(design).optics["f_number"]
    assert ring["radius"] == pytest.approx(1.22 * a.wavelength_nm[0] * 1e-3 * f_number)
    curves = figs[-1]
    assert curves["x"]["view"] == [0.0, 0.5]
    assert len(curves["legend_rows"]) == n + 1
    with pytest.raises(ValueError, match="floor_decades"):
        udc.view_figures(design, floor_decades=-1)
