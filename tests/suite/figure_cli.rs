//! `udc-studio figure`: every display view saved as SVG (well-formed XML carrying the axis
//! titles with their units and the caption) and PNG (at the size asked, its pixels compared
//! with a snapshot per view); bad values refused in one line with nothing written; the
//! studio's Save figure writes the view on screen the same way.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use crate::common::run_cli;

/// The text nodes of an SVG document, failing the test if it is not well-formed XML.
fn svg_texts(path: &Path) -> Vec<String> {
    use quick_xml::events::Event;
    let text = std::fs::read_to_string(path).unwrap();
    let mut reader = quick_xml::Reader::from_str(&text);
    let mut texts = Vec::new();
    let mut depth = 0i64;
    let mut root = None;
    loop {
        match reader.read_event() {
            Ok(Event::Start(e)) => {
                depth += 1;
                root.get_or_insert_with(|| String::from_utf8_lossy(e.name().as_ref()).into_owned());
            }
            Ok(Event::End(_)) => depth -= 1,
            Ok(Event::Text(t)) => {
                let t = t.decode().unwrap().trim().to_owned();
                if !t.is_empty() {
                    texts.push(t);
                }
            }
            Ok(Event::Eof) => break,
            Ok(_) => {}
            Err(e) => panic!("{}: not well-formed XML: {e}", path.display()),
        }
    }
    assert_eq!(depth, 0, "{}: every element closed", path.display());
    assert_eq!(root.as_deref(), Some("svg"), "{}", path.display());
    texts
}

/// `(view, preset, an axis title it must carry, words of its caption)`.
const VIEWS: [(&str, &str, &str, &str); 6] = [
    ("psf", "toled-150dpi", "x (µm)", "pitch 168.0 µm"),
    ("log-psf", "toled-150dpi", "y (µm)", "pitch 168.0 µm"),
    ("rgb", "toled-150dpi", "x (µm)", "pitch 168.0 µm"),
    ("mtf-2d", "toled-150dpi", "νx (cyc/px)", "pitch 168.0 µm"),
    ("mtf", "toled-150dpi", "cycles/pixel", "pitch 168.0 µm"),
    (
        "theory",
        "fourier-slit",
        "position on the sensor, x (µm)",
        "pitch 4200.0 µm",
    ),
];

#[test]
fn every_view_saves_as_svg_and_png_with_axes_units_and_a_caption() {
    let dir = tempfile::tempdir().unwrap();
    for (view, preset, axis, words) in VIEWS {
        let svg = dir.path().join(format!("{view}.svg"));
        let (ok, stdout, stderr) = run_cli(&[
            "figure",
            "--preset",
            preset,
            "--preview",
            "--view",
            view,
            "--out",
            svg.to_str().unwrap(),
            "--json",
        ]);
        assert!(ok, "{view}: {stderr}");
        let j: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
        assert_eq!(j["format"], "svg");
        let caption = j["caption"].as_str().unwrap().to_owned();
        assert!(caption.contains(words), "{caption}");
        let texts = svg_texts(&svg);
        assert!(
            texts.iter().any(|t| t.contains(axis)),
            "{view}: the axis title {axis:?} among {:?}",
            &texts[..texts.len().min(40)]
        );
        assert!(
            texts.iter().any(|t| t.contains(words)),
            "{view}: the caption is drawn"
        );
        // A PNG at a chosen size, its pixels as the snapshot's.
        let png = dir.path().join(format!("{view}.png"));
        let (ok, _, stderr) = run_cli(&[
            "figure",
            "--preset",
            preset,
            "--preview",
            "--view",
            view,
            "--out",
            png.to_str().unwrap(),
            "--width-px",
            "800",
            "--height-px",
            "500",
        ]);
        assert!(ok, "{view}: {stderr}");
        let img = image::open(&png).unwrap().to_rgba8();
        assert_eq!(img.dimensions(), (800, 500), "{view}");
        egui_kittest::image_snapshot(&img, format!("figure-{view}"));
    }
}

#[test]
fn bad_figure_requests_are_refused_in_one_line_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).to_str().unwrap().to_owned();
    let cases: [(&[&str], &str); 8] = [
        (&["--out", &out("a.jpg")], ".svg or .png"),
        (&["--out", &out("a.svg"), "--width-px", "10"], "--width-px"),
        (
            &["--out", &out("a.svg"), "--height-px", "100000"],
            "--height-px",
        ),
        (
            &["--out", &out("a.svg"), "--floor-decades", "-1"],
            "--floor-decades",
        ),
        (
            &["--out", &out("a.svg"), "--floor-decades", "nan"],
            "--floor-decades",
        ),
        (&["--out", &out("a.svg"), "--channel", "X"], "--channel X"),
        (&["--out", &out("a.svg"), "--view", "bogus"], "bogus"),
        // The T-OLED names no closed form.
        (&["--out", &out("a.svg"), "--view", "theory"], "closed form"),
    ];
    for (args, names) in cases {
        let mut all = vec!["figure", "--preset", "toled-150dpi", "--preview"];
        all.extend_from_slice(args);
        let (ok, _, stderr) = run_cli(&all);
        assert!(!ok, "{args:?} was accepted");
        assert!(stderr.contains(names), "{args:?}: {stderr}");
        assert!(
            !stderr.contains("panicked"),
            "{args:?}: a refusal, not a panic: {stderr}"
        );
    }
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "nothing written"
    );
}

/// The Compare tab from the command line: design B's radially-minimum MTFs over design A's,
/// both named in the caption; any other view is refused with a comparison.
#[test]
fn a_comparison_figure_draws_both_designs_and_names_them() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("compare.svg");
    let args = |out: &str| -> Vec<String> {
        [
            "figure",
            "--preset",
            "l2inv-random",
            "--against-preset",
            "toled-150dpi",
            "--preview",
            "--view",
            "mtf",
            "--out",
            out,
        ]
        .map(String::from)
        .to_vec()
    };
    let a = args(svg.to_str().unwrap());
    let (ok, _, stderr) = run_cli(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(ok, "{stderr}");
    let texts = svg_texts(&svg);
    let has = |w: &str| texts.iter().any(|t| t.contains(w));
    assert!(has("cycles/pixel"), "{texts:?}");
    // A's curves carry "A:" in the legend; the caption names B, then A.
    assert!(has("A:"), "design A's curves: {texts:?}");
    assert!(
        has("B: Top-10 L2 + inv, random") && has("A: T-OLED 150 DPI"),
        "{texts:?}"
    );
    let png = dir.path().join("compare.png");
    let mut a = args(png.to_str().unwrap());
    a.extend(["--width-px", "800", "--height-px", "500"].map(String::from));
    let (ok, _, stderr) = run_cli(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(ok, "{stderr}");
    egui_kittest::image_snapshot(&image::open(&png).unwrap().to_rgba8(), "figure-compare");

    let (ok, _, stderr) = run_cli(&[
        "figure",
        "--preset",
        "toled-150dpi",
        "--against-preset",
        "fourier-periodic",
        "--view",
        "log-psf",
        "--out",
        dir.path().join("no.svg").to_str().unwrap(),
    ]);
    assert!(
        !ok && stderr.contains("only the mtf view compares"),
        "{stderr}"
    );
    assert!(!dir.path().join("no.svg").exists());
}

/// The Phase workspace's PSF and MTF plots and the Sensor workspace's maps, written by their
/// commands as figures the same renderer draws: SVG that parses with the axis titles and
/// units, PNG matching a snapshot.
#[test]
fn the_phase_and_sensor_commands_write_their_views_as_figures() {
    let dir = tempfile::tempdir().unwrap();
    let phase = dir.path().join("phase");
    let (ok, _, stderr) = run_cli(&[
        "phase",
        "psf",
        "--preview",
        "--out",
        phase.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    for stem in ["psf-R", "psf-G", "psf-B", "mtf"] {
        let texts = svg_texts(&phase.join(format!("{stem}.svg")));
        let axis = if stem == "mtf" {
            "cycles/pixel"
        } else {
            "sensor pixel from the axis"
        };
        assert!(texts.iter().any(|t| t.contains(axis)), "{stem}: {texts:?}");
        assert!(
            texts.iter().any(|t| t.contains("T-OLED")),
            "{stem}: the legend"
        );
    }
    let png = image::open(phase.join("psf-G.png")).unwrap().to_rgba8();
    egui_kittest::image_snapshot(&png, "figure-phase-psf-G");

    let sensor = dir.path().join("sensor");
    let hdr = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/hdr/StillLife_620x423.exr"
    );
    let (ok, _, stderr) = run_cli(&[
        "sensor",
        "--hdr",
        hdr,
        "--max-side-px",
        "160",
        "--roi",
        "32",
        "--seed",
        "3",
        "--out",
        sensor.to_str().unwrap(),
        "--figures",
    ]);
    assert!(ok, "{stderr}");
    let texts = svg_texts(&sensor.join("scene-figure.svg"));
    assert!(texts.iter().any(|t| t.contains("x (px)")), "{texts:?}");
    let gain = sensor.join("vary-gain_no-bin_gain-figure.svg");
    let texts = svg_texts(&gain);
    assert!(texts.iter().any(|t| t.contains("Gain map")), "{texts:?}");
    assert!(
        sensor.join("const-gain_vary-bin_bins-figure.png").exists(),
        "the bin map"
    );
    let png = image::open(sensor.join("vary-gain_no-bin_gain-figure.png"))
        .unwrap()
        .to_rgba8();
    egui_kittest::image_snapshot(&png, "figure-sensor-gain");
}

/// The Restore view's pictures from `restore --figures`: the capture, the restoration and the
/// difference (brightened), each a picture in pixels that parses as SVG.
#[test]
fn restore_writes_its_pictures_as_figures() {
    let dir = tempfile::tempdir().unwrap();
    let photo = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/photos/astronaut_256.png"
    );
    let out = dir.path().join("restore");
    let (ok, _, stderr) = run_cli(&[
        "restore",
        "--preset",
        "toled-150dpi",
        "--image",
        photo,
        "--max-side-px",
        "64",
        "--snr-db",
        "30",
        "--denoise",
        "none",
        "--out",
        out.to_str().unwrap(),
        "--figures",
    ]);
    assert!(ok, "{stderr}");
    let figures: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with("-figure.svg"))
        .collect();
    for stage in ["captured", "restored", "difference"] {
        let name = figures
            .iter()
            .find(|n| n.ends_with(&format!("_{stage}-figure.svg")))
            .unwrap_or_else(|| panic!("{stage} among {figures:?}"));
        let texts = svg_texts(&out.join(name));
        assert!(
            texts.iter().any(|t| t.contains("x (px)")),
            "{stage}: {texts:?}"
        );
        assert!(
            texts.iter().any(|t| t.contains(stage)),
            "{stage}: the title"
        );
        assert!(out.join(name.replace(".svg", ".png")).exists());
    }
}
