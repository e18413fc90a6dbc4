//! Design files: round trips and clear errors for every kind of bad input.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use proptest::prelude::*;
use udc_studio::core::analysis::analyze::analyze;
use udc_studio::core::design::{Design, Optics, Polygon, TilingMode};
use udc_studio::core::{Progress, SimError};
use udc_studio::io::design::file::{load_design, parse_design, save_design, to_json};

fn arb_design() -> impl Strategy<Value = Design> {
    (
        1usize..12,
        prop::collection::vec(prop::sample::select(vec![0.0, 1.0, 0.25, 0.5]), 144),
        8.0f64..500.0,
        prop::sample::select(TilingMode::ALL.to_vec()),
        any::<u64>(),
        (0.0f64..20.0, 0.0f64..20.0, 0.0f64..10.0),
        prop::bool::ANY,
    )
        .prop_map(|(n, pool, pitch, mode, seed, (ox, oy, gap), phone)| {
            let mut d = Design::default_toled();
            d.opening.pitch_um = pitch;
            d.opening.cells = (0..n).map(|r| pool[r * 12..r * 12 + n].to_vec()).collect();
            if seed % 3 == 0 {
                d.opening.polygons.push(Polygon {
                    vertices_um: vec![[0.0, 0.0], [pitch / 2.0, 0.0], [0.0, pitch / 3.0]],
                });
            }
            d.tiling.mode = mode;
            d.tiling.seed = seed;
            d.tiling.origin_offset_cells = [ox, oy];
            d.tiling.wiring_gap_um = gap;
            if phone {
                d.optics = Optics::phone();
            }
            d
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn any_valid_design_round_trips_exactly(d in arb_design()) {
        prop_assert!(d.validate().is_ok());
        let back = parse_design(&to_json(&d)).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(back, d);
    }
}

#[test]
fn save_then_load_is_identity_and_leaves_no_temp_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("my design.json");
    let mut d = Design::default_toled();
    d.tiling.mode = TilingMode::RandomD4;
    d.tiling.seed = 42;
    save_design(&path, &d).expect("save");
    assert_eq!(load_design(&path).expect("load"), d);
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .expect("list")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(names.len(), 1, "{names:?}");
}

fn err_of(text: &str) -> String {
    parse_design(text)
        .expect_err("must be rejected")
        .to_string()
}

fn good() -> serde_json::Value {
    serde_json::from_str(&to_json(&Design::default_toled())).expect("json")
}

#[test]
fn bad_files_are_rejected_with_the_field_named() {
    let mut v = good();
    v["optics"]["bogus"] = serde_json::json!(1);
    assert!(
        err_of(&v.to_string()).contains("bogus"),
        "{}",
        err_of(&v.to_string())
    );

    let mut v = good();
    v["opening"]["pitch_um"] = serde_json::json!(-3.0);
    assert!(err_of(&v.to_string()).contains("opening.pitch_um"));

    let mut v = good();
    v["optics"]["f_number"] = serde_json::json!("fast");
    assert!(
        err_of(&v.to_string()).contains("optics.f_number"),
        "{}",
        err_of(&v.to_string())
    );

    let mut v = good();
    v["opening"]["cells"][3] = serde_json::json!([1.0, 0.5]);
    assert!(err_of(&v.to_string()).contains("opening.cells[3]"));

    let mut v = good();
    v["opening"]["cells"][0] = serde_json::json!("..x..");
    assert!(err_of(&v.to_string()).contains("unexpected character"));

    let mut v = good();
    v["tiling"]["mode"] = serde_json::json!("hexagonal");
    assert!(err_of(&v.to_string()).contains("tiling.mode"));

    // Recipes are a closed set: an unknown one is refused, naming the field and the choices.
    let mut v = good();
    v["optics"]["recipe"] = serde_json::json!("hubble");
    let e = err_of(&v.to_string());
    assert!(e.contains("optics.recipe") && e.contains("iccp21"), "{e}");

    let mut v = good();
    v["version"] = serde_json::json!(7);
    assert!(err_of(&v.to_string()).contains("version 7"));

    let mut v = good();
    v["channels"][1]["weights"] = serde_json::json!([1.0, 2.0]);
    assert!(err_of(&v.to_string()).contains("channels[1].weights"));

    let text = to_json(&Design::default_toled());
    assert!(
        err_of(&text[..text.len() / 2]).contains("line"),
        "truncated JSON names the line"
    );
    assert!(err_of("[]").contains("not a design file"));
    assert!(err_of("{\"format\": \"something-else\", \"version\": 1}").contains("format"));
}

#[test]
fn missing_and_oversized_files_name_the_path() {
    let dir = tempfile::tempdir().expect("temp dir");
    let missing = dir.path().join("nope.json");
    let e = load_design(&missing).expect_err("missing").to_string();
    assert!(e.contains("nope.json"), "{e}");
    let corrupt = dir.path().join("corrupt.json");
    std::fs::write(&corrupt, b"\xff\xfe garbage").expect("write");
    let e = load_design(&corrupt).expect_err("corrupt").to_string();
    assert!(e.contains("corrupt.json"), "{e}");
}

#[test]
fn nonsense_values_never_reach_the_simulation() {
    type Mutation = Box<dyn Fn(&mut Design)>;
    let cases: Vec<(&str, Mutation)> = vec![
        (
            "optics.f_number",
            Box::new(|d| d.optics.f_number = f64::NAN),
        ),
        (
            "optics.focal_length_mm",
            Box::new(|d| d.optics.focal_length_mm = -1.0),
        ),
        ("optics.window_px", Box::new(|d| d.optics.window_px = 0)),
        (
            "optics.axis_in_pixel_um[0]",
            Box::new(|d| d.optics.axis_in_pixel_um[0] = 2.5),
        ),
        (
            "tiling.wiring_gap_um",
            Box::new(|d| d.tiling.wiring_gap_um = f64::INFINITY),
        ),
        (
            "channels[0].wavelengths_nm[0]",
            Box::new(|d| d.channels[0].wavelengths_nm[0] = -610.0),
        ),
        ("channels", Box::new(|d| d.channels.clear())),
        ("opening.cells", Box::new(|d| d.opening.cells.clear())),
    ];
    for (field, mutate) in cases {
        let mut d = Design::default_toled();
        mutate(&mut d);
        match analyze(&d, &Progress::new()) {
            Err(SimError::InvalidSetting { path: f, .. }) => assert_eq!(f, field),
            other => panic!(
                "{field}: expected an error naming it, got {:?}",
                other.map(|a| a.ltr)
            ),
        }
    }
    // Sizes the machine cannot hold are refused before any allocation.
    let mut d = Design::default_toled();
    d.optics.fine_sample_um = 0.01;
    assert!(matches!(
        analyze(&d, &Progress::new()),
        Err(SimError::TooLarge(_))
    ));
    // A fully closed opening lets no light through.
    let mut d = Design::default_toled();
    d.opening.cells = vec![vec![0.0; 21]; 21];
    let e = analyze(&d, &Progress::new())
        .expect_err("closed")
        .to_string();
    assert!(e.contains("opening.cells") && e.contains("no light"), "{e}");
}

/// Hostile numbers: the extremes a script or a hand-edited file can hold.
fn hostile_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        prop::sample::select(vec![
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            0.0,
            -0.0,
            -1.0,
            1e-300,
            f64::MIN_POSITIVE,
            1e308,
            f64::MAX,
            1e-9,
            1e9,
        ]),
        any::<f64>(),
        0.001f64..1e5,
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    /// Whatever number lands in whichever field, validation answers (no panic), and a design it
    /// accepts has a sampling plan within the limits: no FFT past `MAX_FFT_SIZE`, no pupil past
    /// `MAX_PUPIL_PIXELS` samples. So nothing validated can exhaust memory or loop.
    #[test]
    fn hostile_numbers_are_refused_or_bounded(field in 0usize..12, v in hostile_f64()) {
        use udc_studio::core::design::{MAX_FFT_SIZE, MAX_PUPIL_PIXELS};
        use udc_studio::core::psf::sampling::plan;
        let mut d = Design::default_toled();
        match field {
            0 => d.opening.pitch_um = v,
            1 => d.optics.focal_length_mm = v,
            2 => d.optics.f_number = v,
            3 => d.optics.pupil_sample_um = v,
            4 => d.optics.fine_sample_um = v,
            5 => d.optics.sensor_pixel_um = v,
            6 => d.optics.axis_in_pixel_um[0] = v,
            7 => d.tiling.wiring_gap_um = v,
            8 => d.tiling.origin_offset_cells[1] = v,
            9 => d.channels[1].wavelengths_nm[0] = v,
            10 => d.channels[0].weights[0] = v,
            _ => d.opening.cells[0][0] = v,
        }
        if d.validate().is_ok() {
            let op = &d.optics;
            let across = op.pupil_diameter_um() / d.opening.pitch_um;
            prop_assert!(std::f64::consts::FRAC_PI_4 * across * across <= MAX_PUPIL_PIXELS);
            let mut warnings = Vec::new();
            if let Ok(p) = plan(&d, op.fine_sample_um, &mut warnings) {
                for s in p.iter().flatten() {
                    prop_assert!(s.fft_size <= MAX_FFT_SIZE, "{}", s.fft_size);
                    prop_assert!(s.fine_um.is_finite() && s.fine_um > 0.0);
                }
            }
        }
    }
}
