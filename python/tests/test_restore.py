"""`denoise`, `restore` and `load_photo`: the CLI's runs, the denoiser's gain, bad input."""

import json
import math
import warnings

import numpy as np
import pytest

import udc_studio as udc
from conftest import REPO, assert_ctrl_c_stops, run_cli

PHOTO = REPO / "assets" / "testset" / "coffee.png"


def psnr_db(a, b):
    return 10 * math.log10(1.0 / float(np.mean((a - b) ** 2)))


def smooth_image(shape, seed=0):
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0 : shape[0], 0 : shape[1]] / max(shape)
    base = 0.5 + 0.3 * np.sin(6 * x) * np.cos(4 * y)
    if len(shape) == 3:
        base = np.stack([base * (0.8 + 0.1 * c) for c in range(shape[2])], axis=-1)
    return base, rng


@pytest.mark.parametrize("shape", [(64, 80), (64, 64, 3)])
def test_denoise_removes_most_of_the_noise_and_keeps_the_layout(shape):
    clean, rng = smooth_image(shape)
    sigma = 0.05
    noisy = clean + rng.normal(0, sigma, clean.shape)
    out = udc.denoise(noisy, sigma**2)
    assert out.shape == noisy.shape and out.dtype == np.float64
    assert psnr_db(out, clean) > psnr_db(noisy, clean) + 6


def assert_the_clis_run(cli, ours, *flags):
    """`ours` is the run `udc-studio restore` prints for PHOTO on toled-150dpi with `flags`
    (timings aside); returns its JSON object."""
    theirs = run_cli(cli, "restore", "--preset", "toled-150dpi", "--image", str(PHOTO), *flags, "--json")
    assert theirs.returncode == 0, theirs.stderr
    run = json.loads(theirs.stdout)["runs"][0]
    mine = json.loads(ours.to_json())
    for r in (run, mine):
        r.pop("elapsed_ms", None)
    assert mine == run
    return mine


def test_restore_is_the_clis_run(cli, tmp_path):
    photo = udc.load_photo(PHOTO, max_side_px=96)
    assert photo.shape[2] == 3 and photo.dtype == np.float64 and 0 <= photo.min() <= photo.max() <= 1
    ours = udc.restore("toled-150dpi", photo, snr_db=28)
    assert_the_clis_run(cli, ours, "--max-side-px", "96", "--snr-db", "28")
    assert ours.restored.shape == photo.shape and ours.denoised is not None
    assert ours.psnr_db == pytest.approx(psnr_db(ours.restored, photo), abs=1e-9)


def test_a_matched_sigma2_is_the_default_and_the_clis(cli):
    photo = udc.load_photo(PHOTO, max_side_px=64)
    ours = udc.restore("toled-150dpi", photo, snr_db=24)
    mine = assert_the_clis_run(cli, ours, "--max-side-px", "64", "--snr-db", "24")
    assert mine["denoise"]["sigma2_source"] == "matched"
    # The capture's own variance at white: Poisson, read noise and whole electrons (the JSON
    # rounds to 9 digits).
    e = mine["electrons_per_unit"]
    assert ours.denoise_sigma2 == pytest.approx(1 / e + 4.87**2 / e**2 + 1 / (12 * e**2), rel=1e-6)
    explicit = udc.restore("toled-150dpi", photo, snr_db=24, denoise_sigma2="matched")
    assert explicit.denoise_sigma2 == ours.denoise_sigma2


def test_the_authors_table_is_the_clis(cli):
    photo = udc.load_photo(PHOTO, max_side_px=64)
    ours = udc.restore("toled-150dpi", photo, snr_db=24, denoise_sigma2="table")
    mine = assert_the_clis_run(
        cli, ours, "--max-side-px", "64", "--snr-db", "24", "--denoise-sigma2", "table"
    )
    assert mine["denoise"]["sigma2_source"] == "iccp21"
    # Chapter 3's 0.005 for 24 dB, on our scale (divided by the square of the LTR relative to
    # the reference display).
    r = mine["electrons_per_unit"] / mine["light_e"]
    assert ours.denoise_sigma2 == pytest.approx(0.005 / r**2, rel=1e-6)


def test_the_denoiser_lifts_the_restoration_in_low_light():
    # At 24 dB on a 128-pixel photo BM3D adds about 1.5 dB (the thesis's gain grows with size).
    photo = udc.load_photo(PHOTO, max_side_px=128)
    plain = udc.restore("toled-150dpi", photo, snr_db=24, denoise="none")
    denoised = udc.restore("toled-150dpi", photo, snr_db=24)
    assert plain.denoised is None and plain.denoise_sigma2 is None
    assert denoised.psnr_db > plain.psnr_db + 1.0


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: udc.denoise(np.zeros((0, 0)), 0.01), "planes"),
        (lambda: udc.denoise(np.zeros((16, 16)), float("nan")), "sigma2"),
        (lambda: udc.denoise(np.zeros((16, 16)), 0.0), "sigma2"),
        (lambda: udc.denoise(np.zeros((4, 4, 4, 4)), 0.01), "H×W"),
        (lambda: udc.denoise(np.full((16, 16), np.nan), 0.01), "finite"),
        (lambda: udc.denoise(np.array([["a"]]), 0.01), "unsigned integer pixels"),
        (lambda: udc.restore("toled-150dpi", np.zeros((32, 32, 3))), "exactly one light"),
        (lambda: udc.restore("toled-150dpi", np.zeros((32, 32, 3)), light_e=-5), "light"),
        (lambda: udc.restore("toled-150dpi", np.zeros((32, 32, 3)), snr_db=28, denoise="nlm"), "bm3d"),
        (lambda: udc.restore("toled-150dpi", np.zeros((32, 32, 3)), snr_db=28, method="lucy"), "wiener"),
        (
            lambda: udc.restore("toled-150dpi", np.zeros((32, 32, 3)), snr_db=28, denoise="none", denoise_sigma2=0.01),
            r'^denoise_sigma2=0.01: there is no denoiser to give it to with denoise="none"$',
        ),
        (
            lambda: udc.restore("toled-150dpi", np.zeros((32, 32, 3)), snr_db=28, denoise_sigma2=-1),
            r"^denoise_sigma2=-1.0: the noise variance must be a finite number > 0",
        ),
        (
            lambda: udc.restore("toled-150dpi", np.zeros((32, 32, 3)), snr_db=28, denoise_sigma2=float("nan")),
            r"^denoise_sigma2=NaN: the noise variance must be a finite number > 0",
        ),
        (
            lambda: udc.restore("toled-150dpi", np.zeros((32, 32, 3)), snr_db=28, denoise_sigma2=float("inf")),
            r"^denoise_sigma2=inf: the noise variance must be a finite number > 0",
        ),
        (lambda: udc.restore("toled-150dpi", np.zeros((32, 32)), snr_db=28), "channels"),
        (
            lambda: udc.restore("toled-150dpi", np.zeros((32, 32, 3)), snr_db=28, denoise_sigma2="match"),
            "neither `matched`, `table` nor a number",
        ),
        (
            lambda: udc.restore("toled-150dpi", np.zeros((32, 32, 3)), snr_db=28, denoise_sigma2=b"x"),
            "expected a number, \"matched\" or \"table\"",
        ),
    ],
)
def test_bad_input_raises_value_error(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_integer_pixels_are_scaled_and_results_are_row_major():
    clean, rng = smooth_image((32, 40, 3))
    pixels = np.round(np.clip(clean + rng.normal(0, 0.04, clean.shape), 0, 1) * 255).astype(np.uint8)
    from_bytes = udc.denoise(pixels, 0.04**2)
    from_floats = udc.denoise(pixels / 255.0, 0.04**2)
    np.testing.assert_array_equal(from_bytes, from_floats)
    assert from_bytes.flags.c_contiguous
    photo = udc.load_photo(PHOTO, max_side_px=64)
    assert photo.flags.c_contiguous
    with pytest.raises(ValueError, match="unsigned integer"):
        udc.denoise(np.zeros((16, 16), dtype=np.int32), 0.01)


def test_whole_number_parameters_are_checked():
    with pytest.raises(ValueError, match="max_side_px"):
        udc.load_photo(PHOTO, max_side_px=0)
    image = np.zeros((32, 32, 3))
    for kwargs, name in [({"noise_seed": -1}, "noise_seed"), ({"iterations": 0}, "iterations"),
                         ({"adc_bits": -12}, "adc_bits")]:
        with pytest.raises(ValueError, match=name):
            udc.restore("toled-150dpi", image, snr_db=28, **kwargs)


def test_unreadable_photos_raise_os_error(tmp_path):
    not_an_image = tmp_path / "notes.png"
    not_an_image.write_text("hello")
    with pytest.raises(OSError, match="notes.png"):
        udc.load_photo(not_an_image)
    with pytest.raises(OSError):
        udc.load_photo(tmp_path / "missing.png")


def test_ctrl_c_cancels_a_long_call(tmp_path):
    # CBM3D of a 2048² colour image takes about 14 s on 2 cores; cancelled, it stops at its
    # next check (the image is made once, before the loop of calls).
    assert_ctrl_c_stops(
        "udc.denoise(image, 0.01)", tmp_path, within_s=5.0,
        setup="image = np.random.default_rng(0).random((2048, 2048, 3))",
    )


def test_a_window_that_drops_light_warns_once():
    # Fig. 3.9's 80-DPI base with the P-OLED pattern and the thesis's 294-pixel window: about
    # 3 % of the red light falls outside (conventions.md §5); the shipped 622-pixel window holds it.
    from PIL import Image

    base = REPO / "presets" / "reproduce" / "designs" / "fig3.9" / "base-80dpi.json"
    cells = np.asarray(Image.open(REPO / "presets" / "reproduce" / "patterns" / "poled-42.png")) > 127
    photo = udc.load_photo(PHOTO, max_side_px=32)
    narrow = udc.Design.load(base).with_(opening=cells, optics={"window_px": 294})
    with pytest.warns(UserWarning, match=r"^capture: the 294-pixel PSF window holds .* % in R") as caught:
        udc.restore(narrow, photo, snr_db=32, denoise="none")
    assert len(caught) == 1
    shipped = udc.Design.load(base).with_(opening=cells)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        udc.restore(shipped, photo, snr_db=32, denoise="none")


def test_restore_and_view_figures_take_the_backend(on_gpu):
    """`backend="gpu"`: the design's PSFs from the device, the CPU's restoration to f32
    precision and the adapter named; without an adapter a clear error."""
    photo = udc.load_photo(PHOTO, max_side_px=32)
    cpu = udc.restore("fourier-square", photo, snr_db=28, denoise="none")
    gpu = on_gpu(udc.restore, "fourier-square", photo, snr_db=28, denoise="none")
    assert cpu.adapter is None and gpu.adapter
    assert "backend" not in json.loads(cpu.to_json())
    backend = json.loads(gpu.to_json())["backend"]
    assert (backend["requested"], backend["adapter"]) == ("gpu", gpu.adapter)
    assert backend["device_transforms"] > 0  # the device, not the CPU, computed them
    assert gpu.psnr_db == pytest.approx(cpu.psnr_db, abs=0.01)
    with pytest.raises(ValueError, match="backend"):
        udc.restore("fourier-square", photo, snr_db=28, backend="cuda")
    # The figures' PSFs from the device: the same pictures to f32 precision.
    ours = udc.view_figures("fourier-square", backend="gpu")
    theirs = udc.view_figures("fourier-square")
    assert [f["title"] for f in ours] == [f["title"] for f in theirs]
    psf = [f["images"][0]["values"] for f in (ours[0], theirs[0])]
    assert np.max(np.abs(psf[0] - psf[1])) <= 1e-5 * psf[1].max()
