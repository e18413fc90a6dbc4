//! The typed job layer: a job built from named parameters (a sweep point, a Python call) is the
//! job the command line builds from the same flags, with the same defaults; unknown names and
//! wrong types are refused naming the parameter; and every front end gets the same result.

use clap::Parser;
use serde_json::{Value, json};
use udc_studio::cli::{Cli, Command};
use udc_studio::core::Progress;
use udc_studio::core::sweep::SweepJob;
use udc_studio::jobs::{JobSpec, Params, evaluate};

/// The job the command line `udc-studio WORDS` runs.
fn cli_job(words: &[&str]) -> JobSpec {
    let argv = std::iter::once("udc-studio").chain(words.iter().copied());
    let cli = match Cli::try_parse_from(argv) {
        Ok(c) => c,
        Err(e) => panic!("{words:?}: {e}"),
    };
    use udc_studio::cli::phase::PhaseCommand;
    use udc_studio::cli::sensor::SensorCheck;
    match cli.command {
        Some(Command::Analyze(a)) => JobSpec::Analyze(a.job),
        Some(Command::Restore(a)) => JobSpec::Restore(a.job),
        Some(Command::Phase(PhaseCommand::Psf(a))) => JobSpec::PhasePsf(a.job),
        Some(Command::Phase(PhaseCommand::Invertibility(a))) => JobSpec::PhaseInvertibility(a.job),
        Some(Command::Phase(PhaseCommand::Optimize(a))) => JobSpec::PhaseOptimize(a.job),
        Some(Command::Phase(PhaseCommand::Restore(a))) => JobSpec::PhaseRestore(a.job),
        Some(Command::Sensor(a)) => match a.check {
            Some(SensorCheck::FlatPatch(c)) => JobSpec::SensorFlatPatch(c.job),
            None => JobSpec::Sensor(a.run.job),
        },
        other => panic!("{words:?} is not a job: {other:?}"),
    }
}

fn params(v: Value) -> Params {
    match v {
        Value::Object(m) => m,
        other => panic!("not a map: {other}"),
    }
}

fn from_params(kind: SweepJob, v: Value) -> JobSpec {
    match JobSpec::from_params(kind, &params(v)) {
        Ok(j) => j,
        Err(e) => panic!("{kind:?}: {e:#}"),
    }
}

/// Every parameter of a job, as serde sees it: two jobs with the same value are the same job.
fn value_of(job: &JobSpec) -> Value {
    let v = match job {
        JobSpec::Analyze(j) => serde_json::to_value(j),
        JobSpec::Restore(j) => serde_json::to_value(j),
        JobSpec::PhasePsf(j) => serde_json::to_value(j),
        JobSpec::PhaseInvertibility(j) => serde_json::to_value(j),
        JobSpec::PhaseOptimize(j) => serde_json::to_value(j),
        JobSpec::PhaseRestore(j) => serde_json::to_value(j),
        JobSpec::Sensor(j) => serde_json::to_value(j),
        JobSpec::SensorFlatPatch(j) => serde_json::to_value(j),
    };
    v.expect("a job serialises")
}

/// The defaults are written once: a job with no parameters (or only its required ones) is the
/// job the bare command builds, for every job.
#[test]
fn every_job_has_the_command_lines_defaults() {
    let cases: [(SweepJob, &[&str], Value); 8] = [
        (SweepJob::Analyze, &["analyze"], json!({})),
        (
            SweepJob::Restore,
            &["restore", "--image", "a.png", "--snr-db", "28"],
            json!({"image": "a.png", "snr-db": 28}),
        ),
        (SweepJob::PhasePsf, &["phase", "psf"], json!({})),
        (
            SweepJob::PhaseInvertibility,
            &["phase", "invertibility"],
            json!({}),
        ),
        (SweepJob::PhaseOptimize, &["phase", "optimize"], json!({})),
        (SweepJob::PhaseRestore, &["phase", "restore"], json!({})),
        (
            SweepJob::Sensor,
            &["sensor", "--hdr", "s.exr"],
            json!({"hdr": "s.exr"}),
        ),
        (
            SweepJob::SensorFlatPatch,
            &["sensor", "flat-patch", "--light", "10"],
            json!({"light": 10}),
        ),
    ];
    for (kind, words, given) in cases {
        let from_cli = cli_job(words);
        assert_eq!(from_cli.kind(), kind);
        assert_eq!(
            value_of(&from_params(kind, given)),
            value_of(&from_cli),
            "{words:?}"
        );
    }
}

/// A parameter set by name is the flag of that name, whatever its type: numbers, switches,
/// closed sets by their names, optional values, lists given as a list, a comma text or one value.
#[test]
fn parameters_are_the_flags_by_name() {
    let cases: [(SweepJob, &[&str], Value); 4] = [
        (
            SweepJob::PhaseRestore,
            &[
                "phase",
                "restore",
                "--pitch-um",
                "84",
                "--fold",
                "5",
                "--preview",
                "--relay",
                "whole-display",
                "--photons",
                "250,650",
                "--order",
                "shuffled",
                "--lambda0",
                "uniform",
                "--denoise-sigma2",
                "table",
                "--photo",
                "x.png",
            ],
            json!({"pitch-um": 84, "fold": 5.0, "preview": true, "relay": "whole-display",
                   "photons": "250,650", "order": "shuffled", "lambda0": "uniform",
                   "denoise-sigma2": "table", "photo": "x.png"}),
        ),
        (
            SweepJob::Restore,
            &[
                "restore",
                "--preset",
                "poled-336um",
                "--image",
                "a.png",
                "--light",
                "100",
                "--light",
                "400",
                "--method",
                "cg",
                "--tiling",
                "random-4",
                "--optics",
                "phone",
                "--denoise",
                "none",
            ],
            json!({"preset": "poled-336um", "image": "a.png", "light": [100, 400], "method": "cg",
                   "tiling": "random-4", "optics": "phone", "denoise": "none"}),
        ),
        (
            SweepJob::Sensor,
            &[
                "sensor",
                "--hdr",
                "s.exr",
                "--bin-mode",
                "additive",
                "--additive-gain",
                "same",
                "--roi-light",
                "p99",
                "--cfa",
                "rggb",
                "--max-side-px",
                "64",
            ],
            json!({"hdr": "s.exr", "bin-mode": "additive", "additive-gain": "same",
                   "roi-light": "p99", "cfa": "rggb", "max-side-px": 64}),
        ),
        (
            SweepJob::Analyze,
            &[
                "analyze",
                "presets/toled-150dpi.json",
                "--pitch-um",
                "84",
                "--seed",
                "3",
            ],
            json!({"design": "presets/toled-150dpi.json", "pitch-um": 84, "seed": 3}),
        ),
    ];
    for (kind, words, given) in cases {
        assert_eq!(
            value_of(&from_params(kind, given)),
            value_of(&cli_job(words)),
            "{words:?}"
        );
    }
}

#[test]
fn an_unknown_parameter_or_a_wrong_type_is_refused_by_name() {
    let unknown = JobSpec::from_params(SweepJob::PhasePsf, &params(json!({"pitch": 84})));
    let message = format!("{:#}", unknown.expect_err("unknown name"));
    assert!(message.contains("unknown parameter `pitch`"), "{message}");
    assert!(message.contains("pitch-um"), "lists the names: {message}");

    let wrong = JobSpec::from_params(SweepJob::PhasePsf, &params(json!({"pitch-um": "wide"})));
    let message = format!("{:#}", wrong.expect_err("a word for a number"));
    assert!(message.contains("pitch-um"), "{message}");

    let bad_name = JobSpec::from_params(SweepJob::Sensor, &params(json!({"cfa": "xtrans"})));
    let message = format!("{:#}", bad_name.expect_err("no such member"));
    assert!(
        message.contains("cfa") && message.contains("rggb"),
        "{message}"
    );

    let bad_item = JobSpec::from_params(
        SweepJob::PhaseRestore,
        &params(json!({"photons": "250,lots"})),
    );
    let message = format!("{:#}", bad_item.expect_err("a word in a list"));
    assert!(
        message.contains("photons") && message.contains("lots"),
        "{message}"
    );
}

/// The rules the command line's argument groups enforce hold for a job built from parameters.
#[test]
fn a_restore_job_needs_a_photo_and_a_light_level() {
    let no_light = from_params(SweepJob::Restore, json!({"image": "a.png"}));
    let message = format!("{:#}", no_light.check().expect_err("no light level"));
    assert!(
        message.contains("--light") && message.contains("--snr-db"),
        "{message}"
    );
    let no_image = from_params(SweepJob::Restore, json!({"snr-db": 28}));
    let message = format!(
        "{:#}",
        evaluate(&no_image, &Progress::new()).expect_err("no photo")
    );
    assert!(message.contains("--image"), "{message}");
}

/// One evaluation for every front end: the job from parameters and the job from the command
/// line compute the same object, and its text table carries the same numbers.
#[test]
fn a_job_from_parameters_computes_what_the_command_computes() {
    let from_cli = cli_job(&[
        "phase",
        "psf",
        "--preview",
        "--pitch-um",
        "84",
        "--angle-deg",
        "2",
    ]);
    let from_names = from_params(
        SweepJob::PhasePsf,
        json!({"preview": true, "pitch-um": 84, "angle-deg": 2}),
    );
    let a = evaluate(&from_cli, &Progress::new()).expect("phase psf");
    let b = evaluate(&from_names, &Progress::new()).expect("phase psf");
    assert_eq!(a.json, b.json);
    assert_eq!(a.json["pitch_um"], json!(84.0));
    let ltr = a.json["ltr_with_polariser"].as_f64().expect("ltr");
    assert!(
        a.text.contains(&format!("LTR {:.1} %", 100.0 * ltr)),
        "{}",
        a.text
    );
    assert!(a.text.lines().count() >= 6, "{}", a.text);
}

/// A cancelled progress stops a job at its next check: the caller's cancel reaches it with no
/// thread-local or flag of its own.
#[test]
fn a_cancelled_progress_stops_the_job() {
    let job = from_params(SweepJob::PhaseInvertibility, json!({"preview": true}));
    let progress = Progress::new();
    progress.cancel();
    let e = evaluate(&job, &progress).expect_err("cancelled");
    assert!(format!("{e:#}").contains("cancel"), "{e:#}");
}

/// "Sweep this parameter" is the runner's case of one axis: each of its points resolves to the
/// very design the studio's field edit makes (the same copy, the same custom-recipe rule), for
/// every parameter it offers.
#[test]
fn a_one_axis_sweep_point_is_the_design_with_that_field_set() {
    use udc_studio::core::sweep::Points;
    use udc_studio::core::sweep::one_axis::{SweepMetric, SweepParameter, spec};
    use udc_studio::io::design::hash::design_hash;
    use udc_studio::jobs::sweep::{job_of, point_params};

    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("design.json");
    let design = udc_studio::io::design::presets::load_preset("l2inv-random").expect("preset");
    udc_studio::io::design::file::save_design(&file, &design).expect("save");
    for field in SweepParameter::ALL {
        let current = field.get(&design);
        let values = [current + 1.0, current + 2.0];
        let spec = spec(
            &design,
            &file.to_string_lossy(),
            field,
            &values,
            SweepMetric::Ltr,
            false,
        );
        let points = Points::new(&spec).expect("a valid spec");
        assert_eq!(points.count(), 2);
        for (k, v) in values.iter().enumerate() {
            let job = job_of(spec.job, &point_params(&spec, &points, k as u64)).expect("job");
            let JobSpec::Analyze(job) = job else {
                panic!("{field:?}: not an analysis")
            };
            assert!(job.preview, "preview unless asked for full quality");
            let resolved = job.selection.resolve().expect("resolves");
            let edited = field.apply(&design, *v).expect("a valid value");
            assert_eq!(field.get(&resolved), *v, "{field:?}");
            assert_eq!(
                design_hash(&resolved),
                design_hash(&edited),
                "{field:?} = {v}"
            );
        }
    }
}

/// A bad design value names what the user gave: the flag when a flag set it, the design file's
/// field when the file did.
#[test]
fn a_bad_override_is_named_by_its_flag_and_a_bad_file_by_its_field() {
    for (name, value, flag) in [
        ("f-number", json!(0), "--f-number"),
        ("focal-length-mm", json!(-4.67), "--focal-length-mm"),
        ("sensor-pixel-um", json!(0), "--sensor-pixel-um"),
        ("wiring-gap-um", json!(-1), "--wiring-gap-um"),
        ("pitch-um", json!(-3), "--pitch-um"),
    ] {
        let job = from_params(SweepJob::Analyze, json!({ name: value }));
        let message = format!("{:#}", job.check().expect_err("refused"));
        assert!(
            message.starts_with(&format!("{flag}: ")),
            "{name}: {message}"
        );
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("bad.json");
    let mut design = udc_studio::io::design::presets::load_preset("toled-150dpi").expect("preset");
    design.optics.f_number = 0.0;
    std::fs::write(&file, udc_studio::io::design::file::to_json(&design)).expect("write");
    let job = from_params(SweepJob::Analyze, json!({"design": file.to_string_lossy()}));
    let message = format!("{:#}", job.check().expect_err("refused"));
    assert!(message.contains("optics.f_number"), "{message}");
    assert!(!message.contains("--f-number"), "{message}");
}
