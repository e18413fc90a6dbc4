"""Measured PSFs from Python: a bracket imported with typed arguments, the set read back as
arrays, compared with a design, and a real capture restored with it."""

import numpy as np
import pytest

import udc_studio
from udc_studio import measured


def spot(shape, cy, cx, width, amplitude):
    y, x = np.mgrid[0 : shape[0], 0 : shape[1]]
    return amplitude * np.exp(-((y - cy) ** 2 + (x - cx) ** 2) / (2 * width**2))


def test_a_bracket_imports_with_typed_arguments_and_reads_back_as_arrays(tmp_path):
    rate = spot((64, 64), 30.4, 33.7, 1.6, 2e5)
    for name, t in (("short", 0.1), ("long", 1.0)):
        np.save(tmp_path / f"{name}.npy", np.minimum(rate * t + 100, 65535).astype(np.uint16))
    np.save(tmp_path / "dark.npy", np.full((64, 64), 100, np.uint16))
    result = measured.import_psf(
        [tmp_path / "short.npy", tmp_path / "long.npy"],
        tmp_path / "psf.npy",
        pixel_um=1.4,
        exposures_s=[0.1, 1.0],
        dark=[tmp_path / "dark.npy"],
        wavelength_nm=530,
    )
    report = result["channels"][0]["import"]
    assert report["exposures"] == 2 and report["darks"] == 1
    assert report["saturated_samples"] > 0 and report["clipped_pixels"] == 0
    assert abs(report["centre_px"][0] - 30.4) < 0.05 and abs(report["centre_px"][1] - 33.7) < 0.05
    psf = measured.load(tmp_path / "psf.npy")
    assert psf["pixel_um"] == 1.4 and psf["source"] == "measured"
    (channel,) = psf["channels"]
    assert channel["wavelength_nm"] == 530
    a = channel["psf"]
    n = a.shape[0]
    assert a.shape == (n, n) and abs(a.sum() - 1) < 1e-9
    assert np.unravel_index(a.argmax(), a.shape) == (n // 2, n // 2)


def test_bad_arguments_raise_with_the_flag_named(tmp_path):
    np.save(tmp_path / "a.npy", spot((32, 32), 16, 16, 2, 1000) + 10)
    with pytest.raises(ValueError, match="pixel-um"):
        measured.import_psf(tmp_path / "a.npy", tmp_path / "psf.npy", pixel_um=-1.0)
    with pytest.raises(ValueError, match="unknown field"):
        measured.import_psf(tmp_path / "a.npy", tmp_path / "psf.npy", pixel_um=1.0, colour=3)
    with pytest.raises(OSError, match="nothere"):
        measured.import_psf(tmp_path / "nothere.npy", tmp_path / "psf.npy", pixel_um=1.0)
    assert not (tmp_path / "psf.npy").exists()


def test_compare_and_restore_with_a_design_psf_set(tmp_path):
    # The optimized layout's green PSF as a measurement (no background in it, its peak on the
    # axis): against its own design, and restoring a flat capture.
    analysis = udc_studio.analyze("l2inv-random", quality="full")
    green = analysis.psf[analysis.channels.index("G")]
    np.save(tmp_path / "g.npy", green)
    measured.import_psf(
        tmp_path / "g.npy",
        tmp_path / "set.npy",
        pixel_um=2.0,
        wavelength_nm=float(analysis.wavelength_nm[analysis.channels.index("G")]),
        no_background=True,
        centre="peak",
    )
    result = measured.compare(tmp_path / "set.npy", preset="l2inv-random")
    (row,) = result["channels"]
    assert row["design_channel"] == "G"
    assert row["correlation"] > 0.9
    assert abs(row["auc_measured"] - row["auc_design"]) < 0.02
    truth = np.full((48, 48), 0.5)
    np.save(tmp_path / "truth.npy", truth)
    np.save(tmp_path / "capture.npy", truth)
    restored = measured.restore(
        tmp_path / "set.npy", tmp_path / "capture.npy", truth=tmp_path / "truth.npy", denoise="none"
    )
    # The set's own metadata arrives with the result (the scores' level is the Rust suite's
    # test: a 48² flat field under a 294-px PSF is mostly border).
    assert restored["psf_source"] == "measured"
    assert restored["psf_side_px"] == green.shape[0] and restored["pixel_um"] == 2.0
    assert np.isfinite(restored["psnr_db"]) and restored["denoise_sigma2"] is None


def test_fit_finds_the_design_a_psf_came_from(tmp_path):
    # The 150-DPI T-OLED's green PSF as a measurement, fitted from the same preset over the
    # central 64 pixels: the pitch and the open fraction come back, each with an uncertainty.
    analysis = udc_studio.analyze("toled-150dpi", quality="full")
    g = analysis.channels.index("G")
    np.save(tmp_path / "g.npy", analysis.psf[g])
    measured.import_psf(
        tmp_path / "g.npy",
        tmp_path / "set.npy",
        pixel_um=2.0,
        wavelength_nm=float(analysis.wavelength_nm[g]),
        no_background=True,
        centre="none",
    )
    result = measured.fit(tmp_path / "set.npy", preset="toled-150dpi", window_px=64, no_search=True)
    assert abs(result["pitch_um"]["value"] / 168.0 - 1) < 0.01, result
    assert result["pitch_um"]["sigma"] > 0
    assert abs(result["open_fraction"]["value"] / result["start"]["open_fraction"] - 1) < 0.02
    assert result["residual"] <= result["residual_start"]
    with pytest.raises(ValueError, match="window-px"):
        measured.fit(tmp_path / "set.npy", preset="toled-150dpi", window_px=4)
    # The backend is a closed set: a name outside it is refused before the fit runs.
    with pytest.raises(ValueError, match="cuda"):
        measured.fit(tmp_path / "set.npy", preset="toled-150dpi", backend="cuda")
