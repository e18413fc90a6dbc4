//! `psf import`: frames written by numpy and scipy (`.npy`, MATLAB v5 `.mat`) read to the same
//! array; the three real lab PSFs import with one line naming what was done (the 8-bit PNG with
//! the warning that it is not radiometric); a bracket file; every bad input is one line, exit 1,
//! and nothing written.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};

use crate::common::run_cli as run;

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// The lab PSFs beside the checkout (not in the repository: their licences ask for their own
/// place); `None` where they are not.
fn lab_psfs() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/measured-psf");
    dir.join("diffusercam_psf_16bit.tif")
        .is_file()
        .then_some(dir)
}

/// Runs `python3 -c code` with `dir` as its working folder.
fn python(dir: &Path, code: &str) {
    crate::common::python(dir, code, "numpy and scipy");
}

fn import_json(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["psf", "import", "--json"];
    all.extend_from_slice(args);
    let (ok, stdout, stderr) = run(&all);
    assert!(ok, "psf import {args:?}: {stderr}");
    serde_json::from_str(stdout.trim()).expect("one JSON object")
}

#[test]
fn npy_and_mat_files_written_by_numpy_and_scipy_import_to_the_same_psf() {
    let dir = tempfile::tempdir().unwrap();
    // A Gaussian spot off-centre on a 64×48 frame, with a pedestal, as float32 and as MATLAB's
    // double in a file with two variables (column-major on disk).
    python(
        dir.path(),
        "import numpy as np, scipy.io as sio\n\
         y, x = np.mgrid[0:48, 0:64]\n\
         a = 5.0 + 1000.0 * np.exp(-((y - 20.3)**2 + (x - 30.6)**2) / 8.0)\n\
         np.save('spot.npy', a.astype(np.float32))\n\
         sio.savemat('spot.mat', {'lin_hdr': a, 'note': np.arange(3.0)})\n",
    );
    let npy = import_json(&[
        s(&dir.path().join("spot.npy")),
        "--pixel-um",
        "2",
        "--wavelength-nm",
        "530",
        "--out",
        s(&dir.path().join("a.npy")),
    ]);
    let mat = import_json(&[
        s(&dir.path().join("spot.mat")),
        "--variable",
        "lin_hdr",
        "--pixel-um",
        "2",
        "--out",
        s(&dir.path().join("b.npy")),
    ]);
    for j in [&npy, &mat] {
        let c = &j["channels"][0]["import"]["centre_px"];
        assert!((c[0].as_f64().unwrap() - 20.3).abs() < 0.05, "{c}");
        assert!((c[1].as_f64().unwrap() - 30.6).abs() < 0.05, "{c}");
        let bg = j["channels"][0]["import"]["background"].as_f64().unwrap();
        assert!((bg - 5.0).abs() < 0.01, "background {bg}");
    }
    // The two PSFs (and the sidecar) read back with numpy agree to float32's precision.
    python(
        dir.path(),
        "import numpy as np, json\n\
         a, b = np.load('a.npy'), np.load('b.npy')\n\
         assert a.shape == b.shape and a.shape[0] == a.shape[1], (a.shape, b.shape)\n\
         assert abs(a.sum() - 1) < 1e-9 and abs(b.sum() - 1) < 1e-9\n\
         assert np.abs(a - b).max() < 1e-6 * a.max(), np.abs(a - b).max()\n\
         n = a.shape[0]; assert a[n // 2, n // 2] == a.max()\n\
         side = json.load(open('a.json'))\n\
         assert side['pixel_um'] == 2 and side['channels'][0]['wavelength_nm'] == 530\n\
         assert side['source'] == 'measured'\n",
    );
    // Without --variable the two variables are named; a missing one lists them.
    let (ok, _, err) = run(&[
        "psf",
        "import",
        s(&dir.path().join("spot.mat")),
        "--pixel-um",
        "2",
        "--out",
        s(&dir.path().join("c.npy")),
    ]);
    assert!(
        !ok && err.contains("--variable") && err.contains("lin_hdr") && err.contains("note"),
        "{err}"
    );
    assert!(!dir.path().join("c.npy").exists());
}

#[test]
fn the_lab_psfs_import_each_with_a_line_of_what_was_done() {
    let Some(lab) = lab_psfs() else {
        eprintln!(
            "skipped: the lab PSFs (../shared/data/measured-psf) are not beside this checkout"
        );
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name);
    // The diffuser camera's 16-bit TIFF: a dark background subtracted, its clipped samples
    // counted.
    let d = import_json(&[
        s(&lab.join("diffusercam_psf_16bit.tif")),
        "--pixel-um",
        "3.45",
        "--out",
        s(&out("diffuser.npy")),
    ]);
    let r = &d["channels"][0]["import"];
    assert!(r["clipped_pixels"].as_u64().unwrap() >= 192, "{r}");
    let bg = r["background"].as_f64().unwrap();
    assert!((20.0..60.0).contains(&bg), "background about 32: {bg}");
    assert!(
        d["channels"][0]["summary"]
            .as_str()
            .unwrap()
            .contains("background")
    );
    assert_eq!(d["not_radiometric"], false);
    // The bead's focus stack: a page is chosen, and the best-focused page is brightest.
    let (ok, _, err) = run(&[
        "psf",
        "import",
        s(&lab.join("bead_psf_stack_16bit.tif")),
        "--pixel-um",
        "0.101",
        "--out",
        s(&out("bead.npy")),
    ]);
    assert!(
        !ok && err.contains("61 pages") && err.lines().count() == 1,
        "{err}"
    );
    let peak = |page: &str| {
        let j = import_json(&[
            s(&lab.join("bead_psf_stack_16bit.tif")),
            "--page",
            page,
            "--pixel-um",
            "0.101",
            "--out",
            s(&out(&format!("bead-{page}.npy"))),
        ]);
        j["channels"][0]["import"]["peak_snr"].as_f64().unwrap()
    };
    assert!(peak("31") > 3.0 * peak("1"), "focus is mid-stack");
    // The 8-bit gamma-encoded PNG: imported, with the warning.
    let g = import_json(&[
        s(&lab.join("lenslet_psf_8bit_gamma.png")),
        "--pixel-um",
        "2.4",
        "--crop-px",
        "512",
        "--out",
        s(&out("lenslet.npy")),
    ]);
    assert_eq!(g["not_radiometric"], true);
    let notes = g["notes"].to_string();
    assert!(
        notes.contains("not radiometric") && notes.contains("clipped"),
        "{notes}"
    );
    assert!(
        g["channels"][0]["summary"]
            .as_str()
            .unwrap()
            .contains("hot pixels not looked for")
    );
}

#[test]
fn a_bracket_file_names_exposures_and_darks() {
    let dir = tempfile::tempdir().unwrap();
    // Two exposures of one spot (the longer clips a 16-bit full scale), one dark frame.
    python(
        dir.path(),
        "import numpy as np\n\
         y, x = np.mgrid[0:64, 0:64]\n\
         rate = 2e5 * np.exp(-((y - 31.6)**2 + (x - 33.2)**2) / 6.0)\n\
         for name, t in (('short', 0.1), ('long', 1.0)):\n\
         \x20   np.save(name + '.npy', np.minimum(rate * t + 100, 65535).astype(np.uint16))\n\
         np.save('dark.npy', np.full((64, 64), 100, np.uint16))\n\
         open('bracket.toml', 'w').write('dark = [\"dark.npy\"]\\n[[exposure]]\\nfile = \"short.npy\"\\nexposure_s = 0.1\\n[[exposure]]\\nfile = \"long.npy\"\\nexposure_s = 1.0\\n')\n",
    );
    let j = import_json(&[
        "--bracket",
        s(&dir.path().join("bracket.toml")),
        "--pixel-um",
        "1.4",
        "--out",
        s(&dir.path().join("psf.npy")),
    ]);
    let r = &j["channels"][0]["import"];
    assert_eq!(r["exposures"], 2);
    assert_eq!(r["darks"], 1);
    assert!(r["saturated_samples"].as_u64().unwrap() > 0);
    assert_eq!(r["clipped_pixels"], 0, "the short exposure holds the peak");
    assert!(
        (r["centre_px"][0].as_f64().unwrap() - 31.6).abs() < 0.05,
        "{r}"
    );
}

#[test]
fn bad_frames_are_refused_in_one_line_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    python(
        dir.path(),
        "import numpy as np, scipy.io as sio, os\n\
         y, x = np.mgrid[0:32, 0:32]\n\
         spot = 100 + 1000 * np.exp(-((y - 16)**2 + (x - 16)**2) / 4.0)\n\
         np.save('a.npy', spot)\n\
         np.save('small.npy', spot[:16])\n\
         np.save('flat.npy', np.full((32, 32), 7.0))\n\
         np.save('sat.npy', np.full((32, 32), 65535, np.uint16))\n\
         np.save('cube.npy', np.zeros((2, 3, 4, 5)))\n\
         sio.savemat('other.mat', {'psf_raw': spot})\n\
         open('v73.mat', 'wb').write(b'MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: x HDF5 schema 1.00 .' + bytes(200))\n\
         open('junk.npy', 'wb').write(b'not an array at all')\n",
    );
    let p = |n: &str| dir.path().join(n);
    let out = p("out.npy");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec![
                s(&p("a.npy")).into(),
                s(&p("small.npy")).into(),
                "--exposures-s".into(),
                "1,2".into(),
            ],
            "must be of one size",
        ),
        (
            vec![s(&p("a.npy")).into(), s(&p("a.npy")).into()],
            "2 frames need 2 exposure times",
        ),
        (
            vec![
                s(&p("a.npy")).into(),
                s(&p("a.npy")).into(),
                "--exposures-s".into(),
                "1,-2".into(),
            ],
            "exposure time",
        ),
        (
            vec![
                s(&p("a.npy")).into(),
                s(&p("a.npy")).into(),
                "--exposures-s".into(),
                "1,1e9".into(),
            ],
            "--exposures-s: an exposure time must be",
        ),
        (
            vec![
                s(&p("a.npy")).into(),
                "--wavelength-nm".into(),
                "5e6".into(),
            ],
            "--wavelength-nm: the wavelength must be",
        ),
        (
            vec![s(&p("flat.npy")).into()],
            "no light above the background",
        ),
        (vec![s(&p("sat.npy")).into()], "saturated"),
        (vec![s(&p("cube.npy")).into()], "shape"),
        (
            vec![
                s(&p("other.mat")).into(),
                "--variable".into(),
                "lin_hdr".into(),
            ],
            "no variable `lin_hdr`",
        ),
        (vec![s(&p("v73.mat")).into()], "v7.3"),
        (vec![s(&p("junk.npy")).into()], ".npy"),
        (
            vec![s(&p("a.npy")).into(), "--crop-px".into(), "0".into()],
            "crop_px",
        ),
    ];
    for (extra, want) in cases {
        let mut args = vec!["psf", "import", "--pixel-um", "2", "--out", s(&out)];
        args.extend(extra.iter().map(String::as_str));
        let (ok, _, err) = run(&args);
        assert!(!ok, "{extra:?} was accepted");
        assert!(err.contains(want), "{extra:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{extra:?}: one line: {err}");
        assert!(
            !out.exists() && !p("out.json").exists(),
            "{extra:?} wrote a file"
        );
    }
    for bad in ["0", "-1", "nan", "1e-300", "1e308", "inf"] {
        let (ok, _, err) = run(&[
            "psf",
            "import",
            s(&p("a.npy")),
            "--pixel-um",
            bad,
            "--out",
            s(&out),
        ]);
        assert!(!ok && err.contains("--pixel-um"), "{bad}: {err}");
    }
}

#[test]
fn restore_with_a_psf_set_scores_as_restoring_with_the_simulated_psf() {
    use udc_studio::core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
    use udc_studio::core::measured::PsfSet;
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| dir.path().join(n);
    // A 128² crop of a test photo, the scene.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let photo = image::open(root.join("assets/testset/astronaut.png"))
        .unwrap()
        .crop_imm(160, 80, 128, 128)
        .to_rgb8();
    photo.save(p("scene.png")).unwrap();
    // The capture simulated through the optimized random layout (chapter 3), denoised (BM3D told its own noise) and
    // restored with its own PSF.
    let (ok, stdout, stderr) = run(&[
        "restore",
        "--preset",
        "l2inv-random",
        "--image",
        s(&p("scene.png")),
        "--light",
        "2000",
        "--out",
        s(dir.path()),
        "--json",
    ]);
    assert!(ok, "{stderr}");
    let simulated: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    let psnr_simulated = simulated["runs"][0]["psnr_db"].as_f64().unwrap();
    let sigma2 = simulated["runs"][0]["denoise"]["sigma2"]
        .as_f64()
        .unwrap()
        .to_string();
    // The same PSFs as a PSF set on disk, and the same again through `psf import` (background,
    // centring, crop, normalisation), as a measured set.
    let design = udc_studio::io::design::presets::load_preset("l2inv-random").unwrap();
    let options = AnalyzeOptions {
        quality: Quality::Full,
        expected_psf: false,
    };
    let analysis = analyze_with(&design, &options, &udc_studio::core::Progress::new()).unwrap();
    let set = PsfSet::from_analysis(&analysis);
    udc_studio::io::measured::write_psf_set(&p("simulated.npy"), &set, None).unwrap();
    // The file holds no background (its halo reaches the window's edge, where the import would
    // take it for one); the import centres each channel on its peak.
    let imported = import_json(&[
        s(&p("simulated.npy")),
        "--pixel-um",
        "2",
        "--no-background",
        "--centre",
        "peak",
        "--out",
        s(&p("imported.npy")),
    ]);
    assert_eq!(imported["channels"].as_array().unwrap().len(), 3);
    let restore_with = |psf: &Path| {
        let (ok, stdout, stderr) = run(&[
            "restore",
            "--psf",
            s(psf),
            "--image",
            s(&p("light-2000e_captured.exr")),
            "--truth",
            s(&p("scene.png")),
            "--denoise-sigma2",
            &sigma2,
            "--json",
        ]);
        assert!(ok, "{stderr}");
        let j: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
        j["psnr_db"].as_f64().unwrap()
    };
    let with_set = restore_with(&p("simulated.npy"));
    let with_import = restore_with(&p("imported.npy"));
    assert!(
        psnr_simulated > 15.0,
        "a real restoration: {psnr_simulated:.2} dB"
    );
    assert!(
        (with_set - psnr_simulated).abs() < 0.5,
        "the simulated PSF as a set: {with_set:.2} dB against {psnr_simulated:.2}"
    );
    assert!(
        (with_import - psnr_simulated).abs() < 0.5,
        "the imported PSF: {with_import:.2} dB against {psnr_simulated:.2}"
    );
    // A capture's channels the set cannot serve, and --light with --psf, are refused.
    let (ok, _, err) = run(&[
        "restore",
        "--psf",
        s(&p("simulated.npy")),
        "--image",
        s(&p("scene.png")),
        "--light",
        "100",
    ]);
    assert!(!ok && err.contains("--light"), "{err}");
}

#[test]
fn compare_finds_the_design_a_psf_came_from() {
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| dir.path().join(n);
    // The 150-DPI T-OLED's green PSF as a "measurement" (one channel at its wavelength), the
    // axis on a pixel's centre as an import centres it.
    crate::common::toled_green_set(&p("g.npy"), 168.0, 294);
    let g = p("g.npy");
    let compare = |preset: &str, out: Option<&Path>| {
        let mut args = vec!["psf", "compare", s(&g), "--preset", preset, "--json"];
        if let Some(o) = out {
            args.extend(["--out", s(o)]);
        }
        let (ok, stdout, stderr) = run(&args);
        assert!(ok, "{stderr}");
        let j: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
        j
    };
    let same = compare("toled-150dpi", Some(&p("figures")));
    let other = compare("toled-300dpi", None);
    let row = |j: &serde_json::Value, key: &str| j["channels"][0][key].as_f64().unwrap();
    assert_eq!(
        same["channels"][0]["design_channel"], "G",
        "matched by wavelength"
    );
    assert!(row(&same, "residual_energy_share") < 0.01, "{same}");
    assert!(row(&same, "correlation") > 0.99);
    assert!((row(&same, "auc_measured") - row(&same, "auc_design")).abs() < 0.01);
    // Twice the density is another display: the residual and the AUC say so.
    assert!(row(&other, "residual_energy_share") > 10.0 * row(&same, "residual_energy_share"));
    assert!(row(&other, "correlation") < row(&same, "correlation"));
    for kind in ["profile", "mtf", "residual", "psf-measured", "psf-design"] {
        for ext in ["png", "svg"] {
            let f = p("figures").join(format!("G-{kind}.{ext}"));
            assert!(f.is_file(), "{}", f.display());
        }
    }
}

#[test]
fn fit_from_the_command_line_finds_a_display_at_another_pitch_and_writes_it() {
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| dir.path().join(n);
    // The 150-DPI T-OLED built 10 % coarser than drawn (184.8 µm), seen in green on a 96-pixel
    // window; the fit starts from the preset.
    crate::common::toled_green_set(&p("g.npy"), 184.8, 96);
    let (ok, stdout, stderr) = run(&[
        "psf",
        "fit",
        s(&p("g.npy")),
        "--preset",
        "toled-150dpi",
        "--out",
        s(&p("fitted.json")),
        "--json",
    ]);
    assert!(ok, "{stderr}");
    let j: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    let value = |k: &str| j[k]["value"].as_f64().unwrap();
    assert!((value("pitch_um") / 184.8 - 1.0).abs() < 0.01, "{j}");
    assert!(j["pitch_um"]["sigma"].as_f64().unwrap() > 0.0);
    assert!(
        (value("open_fraction") / j["start"]["open_fraction"].as_f64().unwrap() - 1.0).abs() < 0.02
    );
    assert!(value("rotation_deg").abs() < 0.1, "{j}");
    assert!(j["residual"].as_f64().unwrap() < j["residual_start"].as_f64().unwrap());
    // The fitted design loads, at the fitted pitch.
    let fitted = udc_studio::io::design::file::load_design(&p("fitted.json")).unwrap();
    assert!((fitted.opening.pitch_um - value("pitch_um")).abs() < 1e-9);

    let g = p("g.npy");
    for (args, want) in [
        (vec!["--window-px", "0"], "--window-px"),
        (vec!["--pixel-um", "1e9"], "--pixel-um"),
    ] {
        let mut a = vec!["psf", "fit", s(&g), "--preset", "toled-150dpi"];
        a.extend(args);
        let (ok, _, err) = run(&a);
        assert!(!ok && err.contains(want), "{err}");
        assert_eq!(err.trim().lines().count(), 1, "one line: {err}");
    }
}
