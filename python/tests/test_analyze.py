"""`analyze`: the CLI's numbers to the last digit, arrays with the right shapes and units,
thread safety."""

import json
import threading
import warnings

import numpy as np
import pytest

import udc_studio as udc
from conftest import run_cli

PRESETS = [name for name, _, _ in udc.presets()]


def without_time(text):
    # The time, and the build the command line names in what it prints (`tool_version`).
    report = json.loads(text)
    report.pop("elapsed_ms")
    report.pop("tool_version", None)
    return report


@pytest.mark.parametrize("name", PRESETS)
def test_every_preset_equals_the_cli_json(cli, name):
    theirs = run_cli(cli, "analyze", "--preset", name, "--json")
    assert theirs.returncode == 0, theirs.stderr
    assert without_time(udc.analyze(name).to_json()) == without_time(theirs.stdout)


def test_preview_equals_the_cli_preview(cli):
    theirs = run_cli(cli, "analyze", "--preset", "toled-300dpi", "--preview", "--json").stdout
    ours = udc.analyze("toled-300dpi", quality="preview").to_json()
    assert without_time(ours) == without_time(theirs)


def test_arrays_have_their_shapes_dtypes_and_units():
    a = udc.analyze("toled-150dpi", quality="preview")
    channels, n = len(a.channels), a.window_px
    assert a.psf.shape == (channels, n, n) and a.psf.dtype == np.float64
    assert a.mtf.shape == (channels, n, n)
    # Each PSF sums to 1 over the window (conventions: the light outside it is reported
    # apart, as energy_in_window); the MTF is 1 at zero frequency, the centre.
    np.testing.assert_allclose(a.psf.sum(axis=(1, 2)), 1.0, rtol=1e-9)
    assert np.all((0.9 < a.energy_in_window) & (a.energy_in_window <= 1.0 + 1e-12))
    np.testing.assert_allclose(a.mtf[:, n // 2, n // 2], 1.0, rtol=1e-9)
    assert a.radial_min.shape == (channels, a.freq_cyc_per_px.size)
    assert a.freq_cyc_per_px[0] == 0.0 and a.freq_cyc_per_px[-1] <= 0.5 + 1e-12
    # The AUC is the area under the radially-minimum MTF over cycles per pixel.
    report = json.loads(a.to_json())
    for c, channel in enumerate(report["channels"]):
        assert a.auc[c] == pytest.approx(channel["auc_radial_min"], abs=1e-6)
    assert 0.0 < a.ltr < 1.0 and a.wavelength_nm.tolist() == [610.0, 530.0, 470.0]


def test_the_open_aperture_gives_the_thesis_aucs():
    # Thesis §3.3 (no display): R 0.3068, G 0.3170, B 0.3274.
    a = udc.analyze("open-aperture")
    np.testing.assert_allclose(a.auc, [0.3068, 0.3170, 0.3274], atol=2e-3)


def test_random_tiling_lifts_the_worst_mtf_of_the_same_opening():
    # Thesis Fig. 3.7: the same opening tiled with random orientations has a higher AUC.
    repeat = udc.analyze("l2inv-repeat", quality="preview").auc.mean()
    random = udc.analyze("l2inv-random", quality="preview").auc.mean()
    assert random > repeat


def test_four_threads_at_once_give_the_sequential_results():
    names = ["toled-150dpi", "l2inv-random", "disc-lattice", "fourier-grating"]
    alone = {name: udc.analyze(name, quality="preview") for name in names}
    together, errors = {}, []

    def work(name):
        try:
            together[name] = udc.analyze(name, quality="preview")
        except Exception as e:  # noqa: BLE001 - reported below
            errors.append(e)

    threads = [threading.Thread(target=work, args=(name,)) for name in names]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    for name in names:
        np.testing.assert_array_equal(together[name].psf, alone[name].psf)
        assert without_time(together[name].to_json()) == without_time(alone[name].to_json())


def test_notes_get_a_checked_fix_only_when_asked(cli):
    # toled-150dpi raises a note (light outside the window), not a warning.
    default = json.loads(udc.analyze("toled-150dpi", quality="preview").to_json())
    every = udc.analyze("toled-150dpi", quality="preview", advice="all")
    none = udc.analyze("toled-150dpi", quality="preview", advice="none")
    assert [a["severity"] for a in default["advice"]] == ["note"]
    assert default["advice"][0]["fix"] is None
    assert json.loads(every.to_json())["advice"][0]["fix"]["set"] == {
        "optics.pupil_sample_um": 4.0,
        "optics.window_px": 588,
    }
    assert without_time(none.to_json()) == without_time(json.dumps(default))
    theirs = run_cli(cli, "analyze", "--preset", "toled-150dpi", "--preview", "--advice", "--json")
    assert without_time(every.to_json()) == without_time(theirs.stdout)
    with pytest.raises(ValueError, match="advice"):
        udc.analyze("toled-150dpi", advice="some")


def test_results_compare_by_identity():
    a = udc.analyze("fourier-slit", quality="preview", advice="none")
    assert a == a and a != udc.analyze("fourier-slit", quality="preview", advice="none")


def test_bad_quality_raises():
    with pytest.raises(ValueError, match='"full" or "preview"'):
        udc.analyze("toled-150dpi", quality="best")


def test_the_gpu_backend_gives_the_cpus_numbers_to_f32_precision(on_gpu):
    """On any adapter (a software one included); without one, `gpu` is a clear error."""
    cpu = udc.analyze("toled-150dpi", quality="preview", advice="none")
    gpu = on_gpu(udc.analyze, "toled-150dpi", quality="preview", advice="none")
    assert cpu.adapter is None and gpu.adapter
    # to_json() is the CLI's --json: the backend object where the CPU was not asked for.
    assert "backend" not in json.loads(cpu.to_json())
    backend = json.loads(gpu.to_json())["backend"]
    assert (backend["requested"], backend["adapter"], backend["note"]) == ("gpu", gpu.adapter, None)
    assert backend["device_transforms"] > 0  # the device, not the CPU, computed them
    assert gpu.ltr == cpu.ltr
    assert np.max(np.abs(gpu.psf - cpu.psf)) <= 1e-5 * cpu.psf.max()
    assert np.allclose(gpu.auc, cpu.auc, rtol=3e-3, atol=0)


def test_auto_uses_a_hardware_gpu_or_says_why_not():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        a = udc.analyze("fourier-square", quality="preview", advice="none", backend="auto")
    notes = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
    # Either the PSFs ran on a hardware GPU, or the one line says why they did not.
    assert (a.adapter is not None and not notes) or (
        a.adapter is None and len(notes) == 1 and "computing on the CPU" in notes[0]
    )


def test_bad_backend_raises():
    with pytest.raises(ValueError, match="backend"):
        udc.analyze("fourier-square", backend="cuda")
