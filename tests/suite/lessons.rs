//! The shipped lessons, walked step by step headlessly: every question's right answer, measured
//! on the simulation, agrees with the closed form its explanation names (within the question's
//! tolerance), a right answer is told right and a wrong one wrong. `lesson check` passes every
//! shipped lesson and refuses ten damaged ones in one line each, naming the step and field.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::collections::HashMap;
use std::path::Path;

use udc_studio::core::Analysis;
use udc_studio::core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
use udc_studio::core::design::Channel;
use udc_studio::core::lesson::measure::{Answer, Guess, answer, phase_answer};
use udc_studio::core::lesson::{ChoiceRule, Lesson, Question};
use udc_studio::core::phase::{Incidence, PhaseDesign, PhaseOptics, PhaseSampling, phase_psfs};
use udc_studio::io::design::presets::load_preset;

use crate::common::run_cli;

/// `design` analysed at full quality, as the studio shows a settled result.
fn analysed(design: &udc_studio::core::Design) -> Analysis {
    let options = AnalyzeOptions {
        quality: Quality::Full,
        expected_psf: false,
    };
    analyze_with(design, &options, &udc_studio::core::Progress::new()).unwrap()
}

fn analysis_of(preset: &str, cache: &mut HashMap<String, Analysis>) -> Analysis {
    cache
        .entry(preset.to_owned())
        .or_insert_with(|| analysed(&load_preset(preset).unwrap()))
        .clone()
}

/// Walks `file`'s steps as the studio does (a step without a preset keeps the design on
/// screen) and checks every question; returns how many were asked.
fn walk(file: &str) -> usize {
    let (_, text) = udc_studio::io::lesson::SHIPPED
        .iter()
        .find(|(name, _)| *name == file)
        .unwrap();
    let lesson: Lesson = udc_studio::io::lesson::parse_lesson(text).unwrap();
    let mut cache = HashMap::new();
    let mut on_screen = None;
    let mut phase_design: Option<PhaseDesign> = None;
    let mut asked = 0;
    for (i, step) in lesson.steps.iter().enumerate() {
        let at = format!("{file} step {}", i + 1);
        if let Some(p) = &step.preset {
            on_screen = Some(p.clone());
        }
        if let Some(c) = &step.phase {
            let start = phase_design
                .clone()
                .unwrap_or_else(|| PhaseDesign::thesis(1.0, 1.0));
            phase_design = Some(c.apply(&start));
        }
        if let Some(q) = step.question.as_ref().filter(|q| is_phase(q)) {
            // The Phase workspace's PSFs as the studio computes them by default.
            let design = phase_design.clone().expect("a phase step came first");
            let psfs = phase_psfs(
                &design,
                &PhaseSampling::for_quality(Quality::Full),
                &Channel::rgb_peaks(),
                PhaseOptics::DoubleMla,
                Incidence::AngleDeg(0.0),
                &udc_studio::core::Progress::new(),
            )
            .unwrap();
            let a = phase_answer(q, &design, &psfs).unwrap();
            asked += 1;
            check_answer(&at, &a, q, &step.explain);
            continue;
        }
        let preset = on_screen.clone().unwrap();
        let (design, analysis) = match &step.change {
            // A change edits the design on screen: the step sees the changed one.
            Some(c) => {
                let d = c.apply(&load_preset(&preset).unwrap());
                let a = analysed(&d);
                (d, a)
            }
            None => (
                load_preset(&preset).unwrap(),
                analysis_of(&preset, &mut cache),
            ),
        };
        let Some(q) = &step.question else {
            assert!(
                !step.explain.contains('{'),
                "{at}: a placeholder without a question"
            );
            continue;
        };
        asked += 1;
        let other = match q {
            Question::Choice { than: Some(t), .. } => Some(analysis_of(t, &mut cache)),
            _ => None,
        };
        let a = answer(q, &design, &analysis, other.as_ref()).unwrap();
        check_answer(&at, &a, q, &step.explain);
    }
    asked
}

/// Whether the studio measures `q` on the Phase workspace.
fn is_phase(q: &Question) -> bool {
    match q {
        Question::Number { quantity, .. } => quantity.is_phase(),
        Question::Choice { rule, .. } => *rule == ChoiceRule::MostLightChannel,
        Question::Drawing { .. } => false,
    }
}

/// The measured answer `a` to `q` agrees with the closed form its explanation names, right is
/// graded right and wrong wrong.
fn check_answer(at: &str, a: &Answer, q: &Question, explain: &str) {
    {
        let explained = a.explain(explain);
        assert!(!explained.contains('{'), "{at}: {explained}");
        match (a, q) {
            (Answer::Number { value, closed, .. }, Question::Number { tolerance, .. }) => {
                let closed = closed.expect("a number question names its closed form");
                assert!(
                    (closed - value).abs() <= tolerance * value.abs(),
                    "{at}: simulated {value}, closed form {closed}, tolerance {tolerance}"
                );
                assert!(
                    a.grade(Guess::Number(*value), *tolerance),
                    "{at}: right is right"
                );
                assert!(
                    a.grade(Guess::Number(closed), *tolerance),
                    "{at}: the closed form's value is a right answer"
                );
                let wrong = value * (1.0 + 3.0 * tolerance);
                assert!(
                    !a.grade(Guess::Number(wrong), *tolerance),
                    "{at}: wrong is wrong"
                );
            }
            (
                Answer::Choice {
                    options,
                    right,
                    closed,
                },
                Question::Choice { .. },
            ) => {
                if let Some(c) = closed {
                    assert_eq!(c, right, "{at}: the closed form picks {}", options[*c]);
                }
                assert!(a.grade(Guess::Choice(*right), 0.0));
                for k in (0..options.len()).filter(|k| k != right) {
                    assert!(
                        !a.grade(Guess::Choice(k), 0.0),
                        "{at}: {} is wrong",
                        options[k]
                    );
                }
            }
            (Answer::Drawing { share, closed, met }, Question::Drawing { .. }) => {
                // The preset is the starting point: its orders are there until drawn away.
                assert!(!met, "{at}: the goal is not met before drawing ({share})");
                assert!(!a.grade(Guess::Drawn, 0.0), "{at}: not done is told so");
                assert!(
                    (share - closed).abs() <= 0.1 * closed,
                    "{at}: simulated {share}, Fourier series {closed}"
                );
            }
            _ => panic!("{at}: the answer's kind is not the question's"),
        }
    }
}

macro_rules! lesson_test {
    ($name:ident, $file:literal, $questions:literal) => {
        #[test]
        fn $name() {
            assert_eq!(walk($file), $questions, "questions asked");
        }
    };
}

lesson_test!(
    the_slit_lesson_agrees_with_lambda_f_over_a,
    "01-slit.toml",
    1
);
lesson_test!(
    the_circle_lesson_agrees_with_the_airy_radius,
    "02-circle.toml",
    1
);
lesson_test!(
    the_double_slit_lesson_agrees_with_lambda_f_over_d,
    "03-double-slit.toml",
    1
);
lesson_test!(
    the_grating_lesson_agrees_with_the_orders_and_their_weights,
    "04-grating.toml",
    3
);
lesson_test!(
    the_convolution_lesson_agrees_with_the_lattice_and_the_envelope,
    "05-convolution.toml",
    2
);
lesson_test!(
    the_random_tiling_lesson_finds_the_higher_auc,
    "06-random-tiling.toml",
    1
);
lesson_test!(
    the_sampling_lesson_agrees_with_nyquist,
    "07-sampling.toml",
    1
);
lesson_test!(the_colour_lesson_finds_red_widest, "08-colour.toml", 1);
lesson_test!(the_mystery_lesson_walks, "09-mystery.toml", 0);
lesson_test!(
    the_drawing_lesson_starts_with_orders_to_remove,
    "10-draw.toml",
    1
);
lesson_test!(
    the_microlens_lesson_agrees_with_p_over_a_and_the_folding_wavelength,
    "11-microlens-arrays.toml",
    3
);

#[test]
fn a_horizontal_band_across_the_pixel_has_no_horizontal_orders_and_is_graded_right() {
    use udc_studio::core::lesson::DrawingGoal;
    let (_, text) = udc_studio::io::lesson::SHIPPED
        .iter()
        .find(|(name, _)| *name == "10-draw.toml")
        .unwrap();
    let lesson = udc_studio::io::lesson::parse_lesson(text).unwrap();
    let q = lesson.steps[1].question.clone().unwrap();
    assert!(matches!(
        q,
        Question::Drawing {
            goal: DrawingGoal::NoHorizontalOrders,
            ..
        }
    ));
    // The student's drawing: the grating's pixel with a band of six whole rows open instead.
    let mut drawn = load_preset("fourier-grating").unwrap();
    let n = drawn.opening.n();
    for (r, row) in drawn.opening.cells.iter_mut().enumerate() {
        let open = (7..13).contains(&r);
        row.iter_mut()
            .for_each(|t| *t = if open { 1.0 } else { 0.0 });
    }
    assert_eq!(drawn.opening.cells.len(), n);
    let analysis = analysed(&drawn);
    let a = answer(&q, &drawn, &analysis, None).unwrap();
    let Answer::Drawing { share, closed, met } = a.clone() else {
        panic!("{a:?}")
    };
    assert!(met, "the band leaves {share} in the horizontal orders");
    assert!(
        closed < 1e-9,
        "the Fourier series puts none there: {closed}"
    );
    assert!(a.grade(Guess::Drawn, 0.0));
}

#[test]
fn the_mystery_aperture_scores_itself_fully_and_another_opening_lower() {
    use udc_studio::core::lesson::measure::psf_match;
    let (_, text) = udc_studio::io::lesson::SHIPPED
        .iter()
        .find(|(name, _)| *name == "09-mystery.toml")
        .unwrap();
    let lesson = udc_studio::io::lesson::parse_lesson(text).unwrap();
    let step = &lesson.steps[0];
    let mut cache = HashMap::new();
    let mystery = analysis_of(step.mystery.as_deref().unwrap(), &mut cache);
    let canvas = analysis_of(step.preset.as_deref().unwrap(), &mut cache);
    let random = analysis_of("fourier-random", &mut cache);
    let itself = psf_match(&mystery, &mystery, "G").unwrap();
    assert!((itself - 1.0).abs() < 1e-12, "{itself}");
    let start = psf_match(&canvas, &mystery, "G").unwrap();
    let far = psf_match(&random, &mystery, "G").unwrap();
    assert!(start < 0.9, "the starting L is not the grating: {start}");
    assert!(
        far < start,
        "a random tiling is further from it than the periodic L: {far} ≥ {start}"
    );
}

#[test]
fn a_change_the_studio_cannot_make_is_refused_naming_its_step() {
    let (_, text) = udc_studio::io::lesson::SHIPPED
        .iter()
        .find(|(name, _)| *name == "04-grating.toml")
        .unwrap();
    for (bad, words) in [
        ("pitch_um = 0.0", "step 4, change.pitch_um: 0"),
        ("tiling = \"hexagonal\"", "step 4, change.tiling"),
    ] {
        let damaged = text.replace("pitch_um = 320.0", bad);
        let e = udc_studio::io::lesson::parse_lesson(&damaged).unwrap_err();
        assert!(e.contains(words), "{bad}: {e}");
        assert!(!e.contains('\n'), "one line: {e}");
    }
}

#[test]
fn every_shipped_lesson_is_a_file_in_the_lessons_folder() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/lessons");
    let mut on_disk: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    on_disk.sort();
    let shipped: Vec<&str> = udc_studio::io::lesson::SHIPPED
        .iter()
        .map(|(n, _)| *n)
        .collect();
    assert_eq!(on_disk, shipped);
    assert!(shipped.len() >= 10);
}

#[test]
fn lesson_check_passes_the_shipped_lessons_and_refuses_damaged_ones_in_one_line() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/lessons");
    let files: Vec<String> = udc_studio::io::lesson::SHIPPED
        .iter()
        .map(|(n, _)| dir.join(n).to_str().unwrap().to_owned())
        .collect();
    let mut args = vec!["lesson", "check"];
    args.extend(files.iter().map(String::as_str));
    let (ok, stdout, stderr) = run_cli(&args);
    assert!(ok, "{stderr}");
    assert_eq!(
        stdout.lines().filter(|l| l.contains(": ok")).count(),
        files.len()
    );

    let good = std::fs::read_to_string(dir.join("01-slit.toml")).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    // (what is broken, the damaged text, words the one line must hold)
    let damaged: [(&str, String, &[&str]); 10] = [
        (
            "not TOML",
            good.replace("title = \"A single", "title = A single"),
            &["line"],
        ),
        (
            "format",
            good.replace("udc-studio-lesson", "udc-studio-design"),
            &["format"],
        ),
        (
            "version",
            good.replace("version = 1", "version = 2"),
            &["version", "2"],
        ),
        (
            "missing look",
            good.replacen("look = \"Switch", "lok = \"Switch", 1),
            &["step 2", "lok"],
        ),
        (
            "unknown preset",
            good.replace("fourier-slit", "fourier-slot"),
            &["step 1", "preset", "fourier-slot"],
        ),
        (
            "tolerance",
            good.replace("tolerance = 0.1", "tolerance = 1.5"),
            &["step 2", "question.tolerance"],
        ),
        (
            "quantity",
            good.replace("first-dark-um", "first-bright-um"),
            &["step 2", "question", "first-bright-um"],
        ),
        (
            "first step",
            good.replacen("preset = \"fourier-slit\"\n", "", 1),
            &["step 1", "preset"],
        ),
        (
            "placeholder",
            good.replace("{closed}", "{closd}"),
            &["step 2", "explain", "{closd}"],
        ),
        (
            "no steps",
            good.split("[[step]]").next().unwrap().to_owned(),
            &["step"],
        ),
    ];
    for (what, text, words) in damaged {
        assert_ne!(text, good, "{what}: the damage applied");
        let path = tmp.path().join(format!("{}.toml", what.replace(' ', "-")));
        std::fs::write(&path, &text).unwrap();
        let (ok, _, stderr) = run_cli(&["lesson", "check", path.to_str().unwrap()]);
        assert!(!ok, "{what}: accepted");
        let first = stderr.lines().next().unwrap_or_default();
        for w in words {
            assert!(first.contains(w), "{what}: {w:?} not in {first:?}");
        }
        assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    }
}

#[test]
fn a_phase_step_the_studio_cannot_set_up_is_refused_naming_its_step() {
    let (_, text) = udc_studio::io::lesson::SHIPPED
        .iter()
        .find(|(name, _)| *name == "11-microlens-arrays.toml")
        .unwrap();
    for (from, to, words) in [
        // The lesson cannot know what phase design is on screen.
        ("from_thesis = true, ", "", "step 1, phase.from_thesis"),
        (
            "lambda0_nm = 610.0",
            "lambda0_nm = 900.0",
            "step 3, phase.lambda0_nm: 900",
        ),
        (
            "phase = { from_thesis = true, lambda0_nm = 530.0 }",
            "preset = \"fourier-slit\"",
            "step 1, question: measures a phase-mask design",
        ),
    ] {
        let damaged = text.replacen(from, to, 1);
        assert_ne!(&damaged, text, "{from}: the damage applied");
        let e = udc_studio::io::lesson::parse_lesson(&damaged).unwrap_err();
        assert!(e.contains(words), "{from}: {e}");
        assert!(!e.contains('\n'), "one line: {e}");
    }
}

/// A teacher's own mystery: a design file beside the lesson, found relative to it; a missing
/// or broken one is refused naming the step and the field.
#[test]
fn a_mystery_from_a_teachers_design_file_is_read_beside_the_lesson() {
    let (_, text) = udc_studio::io::lesson::SHIPPED
        .iter()
        .find(|(name, _)| *name == "09-mystery.toml")
        .unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let mut secret = load_preset("fourier-double-slit").unwrap();
    secret.name = "the teacher's secret".into();
    udc_studio::io::design::file::save_design(&tmp.path().join("secret.json"), &secret).unwrap();
    let lesson_text = text.replace(
        "mystery = \"fourier-grating\"",
        "mystery_file = \"secret.json\"",
    );
    assert_ne!(&lesson_text, text);
    let path = tmp.path().join("mine.toml");
    std::fs::write(&path, &lesson_text).unwrap();
    let lesson = udc_studio::io::lesson::read_lesson(&path).unwrap();
    let Some(udc_studio::core::lesson::MysterySource::File(found)) =
        lesson.steps[0].mystery_source()
    else {
        panic!("{:?}", lesson.steps[0])
    };
    let read = udc_studio::io::design::file::load_design(found).unwrap();
    assert_eq!(read.name, "the teacher's secret");
    let (ok, stdout, stderr) = run_cli(&["lesson", "check", path.to_str().unwrap()]);
    assert!(ok && stdout.contains(": ok"), "{stdout}{stderr}");

    std::fs::remove_file(tmp.path().join("secret.json")).unwrap();
    let (ok, _, stderr) = run_cli(&["lesson", "check", path.to_str().unwrap()]);
    assert!(!ok);
    let first = stderr.lines().next().unwrap_or_default();
    assert!(
        first.contains("step 1, mystery_file") && first.contains("secret.json"),
        "{first}"
    );
    // A preset and a file at once is ambiguous.
    let both = lesson_text.replace(
        "mystery_file = \"secret.json\"",
        "mystery = \"fourier-grating\"\nmystery_file = \"secret.json\"",
    );
    let e = udc_studio::io::lesson::parse_lesson(&both).unwrap_err();
    assert!(e.contains("step 1, mystery_file"), "{e}");
}
