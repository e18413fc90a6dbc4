//! The CLI contract: names other tools depend on, one-line errors, non-zero exits.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common::{run_cli as run, run_cli_timed as run_timed};

#[test]
fn analyze_json_has_the_contract_fields() {
    let (ok, stdout, stderr) = run(&["analyze", "--preset", "open-aperture", "--json"]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).expect("one JSON object");
    for key in [
        "open_fraction",
        "ltr",
        "invertibility_loss",
        "warnings",
        "elapsed_ms",
        "channels",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    let names: Vec<&str> = v["channels"]
        .as_array()
        .expect("array")
        .iter()
        .map(|c| c["name"].as_str().expect("name"))
        .collect();
    assert_eq!(names, ["R", "G", "B"]);
    let r = &v["channels"][0];
    assert_eq!(r["wavelength_nm"], 610.0);
    assert_eq!(r["fft_size"], 1524);
    for key in [
        "auc_radial_min",
        "auc_radial_mean",
        "radial_min",
        "radial_mean",
        "mtf_horizontal",
        "mtf_vertical",
        "energy_in_window",
    ] {
        assert!(r.get(key).is_some(), "channel missing {key}");
    }
    assert_eq!(r["radial_min"].as_array().expect("array").len(), 147);
    let auc = r["auc_radial_min"].as_f64().expect("number");
    assert!((auc - 0.3068).abs() / 0.3068 < 0.003, "{auc}");
}

#[test]
fn overrides_change_the_design() {
    let (ok, a, e) = run(&["analyze", "--preset", "toled-150dpi", "--json", "--preview"]);
    assert!(ok, "{e}");
    let (ok, b, e) = run(&[
        "analyze",
        "--preset",
        "toled-150dpi",
        "--json",
        "--preview",
        "--tiling",
        "random-d4",
        "--seed",
        "3",
    ]);
    assert!(ok, "{e}");
    let auc = |s: &str| {
        serde_json::from_str::<serde_json::Value>(s.trim()).expect("json")["channels"][0]["auc_radial_min"].as_f64().expect("number")
    };
    assert!(
        auc(&b) > 3.0 * auc(&a),
        "random tiling must lift the AUC: {} vs {}",
        auc(&b),
        auc(&a)
    );
}

#[test]
fn bad_input_gives_one_line_and_a_failure_code() {
    for args in [
        vec!["analyze", "--preset", "no-such-preset"],
        vec!["analyze", "/definitely/missing.json"],
        vec!["analyze", "--pitch-um=-5"],
        vec!["analyze", "--pitch-um", "NaN"],
        vec!["analyze", "--optics", "telescope"],
        vec!["analyze", "--pattern", "/definitely/missing.png"],
    ] {
        let (ok, stdout, stderr) = run(&args);
        assert!(!ok, "{args:?} must fail");
        assert!(stdout.is_empty(), "{args:?} printed {stdout}");
        assert_eq!(stderr.trim().lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.starts_with("error: "), "{stderr}");
    }
    let (ok, _, stderr) = run(&["analyze", "--tiling", "hexagonal"]);
    assert!(!ok && stderr.contains("hexagonal"));
}

/// `presets --json` is the scripts' form: every preset once, with its group and description.
#[test]
fn presets_json_lists_every_preset_with_its_group_and_description() {
    let (ok, stdout, stderr) = run(&["presets", "--json"]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).expect("one JSON object");
    let rows = v["presets"].as_array().expect("a presets array");
    let names: Vec<&str> = rows.iter().filter_map(|r| r["name"].as_str()).collect();
    let want: Vec<&str> = udc_studio::io::design::presets::PRESETS
        .iter()
        .map(|p| p.name)
        .collect();
    assert_eq!(names, want);
    for r in rows {
        let group = r["group"].as_str().unwrap_or("");
        assert!(["thesis", "fourier-optics"].contains(&group), "{r}");
        assert!(!r["description"].as_str().unwrap_or("").is_empty(), "{r}");
    }
    let slit = rows
        .iter()
        .find(|r| r["name"] == "fourier-slit")
        .expect("slit");
    assert_eq!(slit["group"], "fourier-optics");
}

#[test]
fn presets_lists_every_named_preset() {
    let (ok, stdout, _) = run(&["presets"]);
    assert!(ok);
    for name in [
        "open-aperture",
        "toled-150dpi",
        "toled-300dpi",
        "toled-600dpi",
        "poled-336um",
        "disc-lattice",
        "l2-repeat",
        "l2inv-repeat",
        "l2-random",
        "l2inv-random",
        "fourier-slit",
        "fourier-random",
    ] {
        assert!(
            stdout.lines().any(|l| l.trim_start().starts_with(name)),
            "missing {name}"
        );
    }
    // Grouped: the teaching presets under their own heading, after the thesis's.
    let thesis = stdout.find("Thesis designs:").unwrap();
    let fourier = stdout.find("Fourier optics (teaching):").unwrap();
    assert!(thesis < fourier && fourier < stdout.find("fourier-slit").unwrap());
}

#[test]
fn spectral_channels_from_a_csv() {
    let csv = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/spectral/thesis_sensor_response.csv"
    );
    let (ok, stdout, stderr) = run(&[
        "analyze",
        "--preset",
        "open-aperture",
        "--json",
        "--preview",
        "--spectral",
        csv,
        "--spectral-step-nm",
        "50",
    ]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).expect("json");
    let g = &v["channels"][1];
    let n = g["wavelengths_nm"].as_array().expect("array").len();
    assert!(n >= 5, "sampled every 50 nm over the table: {n}");
    let mean = g["wavelength_nm"].as_f64().expect("number");
    assert!(
        (500.0..570.0).contains(&mean),
        "green's weighted mean wavelength {mean}"
    );
    let (ok, _, stderr) = run(&["analyze", "--spectral", "/missing.csv"]);
    assert!(!ok && stderr.contains("missing.csv"), "{stderr}");
}

#[test]
fn sizes_that_would_take_minutes_are_refused_at_once_with_the_limit() {
    // A 0.1 µm pitch would sample the pupil with ~10⁸ pixels: refused before any FFT, naming the
    // smallest pitch that fits.
    let (code, stdout, stderr, took) = run_timed(&["analyze", "--pitch-um", "0.1", "--preview"]);
    assert_eq!(code, Some(1), "{stdout}{stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(stderr.contains("at least"), "{stderr}");
    assert!(took < std::time::Duration::from_secs(5), "{took:?}");
    // A spectral step of 1e-9 nm would make 10¹¹ wavelengths.
    let csv = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/spectral/thesis_sensor_response.csv"
    );
    let (code, _, stderr, took) = run_timed(&[
        "analyze",
        "--spectral",
        csv,
        "--spectral-step-nm",
        "1e-9",
        "--preview",
    ]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("--spectral-step-nm"), "{stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(took < std::time::Duration::from_secs(5), "{took:?}");
}

#[test]
fn negative_numbers_reach_validation_and_usage_errors_are_one_line() {
    let photo = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/photos/astronaut_256.png"
    );
    // A negative SNR parses as a value (not as an unknown flag) and is judged by the physics:
    // −1000 dB is far less than one electron.
    for light in [
        ["--snr-db", "-1000"],
        ["--snr-db", "1000"],
        ["--light", "1e-300"],
        ["--light", "1e308"],
    ] {
        let mut args = vec!["restore", "--image", photo, "--max-side-px", "32"];
        args.extend(light);
        let (code, stdout, stderr, _) = run_timed(&args);
        assert_eq!(code, Some(1), "{light:?}: {stdout}{stderr}");
        assert!(stderr.contains("electrons at white"), "{stderr}");
        // Named by the flag the user typed, not the core's field name.
        assert!(
            stderr.starts_with(&format!("error: {}: ", light[0])),
            "{stderr}"
        );
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    }
    // Usage errors: one line, exit code 2, pointing at --help.
    for args in [
        vec!["analyze", "--bogus"],
        vec!["restore", "--image", photo],
        vec!["analyze", "--pitch-um"],
    ] {
        let (code, _, stderr, _) = run_timed(&args);
        assert_eq!(code, Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.ends_with("(see --help)\n"), "{stderr}");
    }
}

#[test]
fn jobs_over_the_memory_budget_are_refused_before_they_start() {
    let photo = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/photos/astronaut_256.png"
    );
    let hdr = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/hdr/StillLife_620x423.exr"
    );
    // 256² photo: ~17 MB by the estimate; an 8 MiB budget refuses it, naming the flag.
    for args in [
        vec![
            "--max-memory",
            "8M",
            "restore",
            "--image",
            photo,
            "--snr-db",
            "28",
        ],
        vec!["sensor", "--hdr", hdr, "--max-memory", "8M"],
    ] {
        let (code, stdout, stderr, _) = run_timed(&args);
        assert_eq!(code, Some(1), "{args:?}: {stdout}{stderr}");
        assert!(stdout.is_empty(), "{args:?} started: {stdout}");
        assert!(
            stderr.contains("needs about") && stderr.contains("--max-memory"),
            "{stderr}"
        );
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    }
    // The same jobs run under a budget that fits them.
    let (code, _, stderr, _) = run_timed(&[
        "--max-memory",
        "1G",
        "restore",
        "--image",
        photo,
        "--snr-db",
        "28",
    ]);
    assert_eq!(code, Some(0), "{stderr}");
    let (code, _, stderr, _) = run_timed(&["--max-memory", "1G", "sensor", "--hdr", hdr]);
    assert_eq!(code, Some(0), "{stderr}");
    // A size that is not one is a usage error.
    let (code, _, stderr, _) = run_timed(&["--max-memory", "lots", "presets"]);
    assert_eq!(code, Some(2), "{stderr}");
}
