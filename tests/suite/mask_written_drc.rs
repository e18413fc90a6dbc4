//! The design-rule check of the written mask, judged by KLayout: for every preset, region kind
//! (one pixel, a 3 × 3 block, the lens pupil) and tone, under the default border policy (and
//! under `cut` for the presets whose openings cross pixel edges), the width, space and corner findings the export reports equal those of
//! KLayout's own checks run from the `.lydrc` deck the export writes, on the same file; and
//! `udc-studio drc FILE` reading the file back reports what the export did. Needs python3 with
//! klayout (`.ci/test` installs it).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::run_cli;
use udc_studio::core::Progress;
use udc_studio::core::design::Design;
use udc_studio::core::mask::drc::{Rules, ViolationKind};
use udc_studio::core::mask::{BorderPolicy, MaskRegion, MaskSpec, Tone};
use udc_studio::io::design::presets::{PRESETS, load_preset};
use udc_studio::io::mask::{
    CheckScope, ChecksumCheck, ExportOptions, MaskFormat, check_file, drc_deck, export_mask,
};

/// Rules coarse enough that most presets break some: findings to compare, not just zeros.
fn rules() -> Rules {
    Rules {
        min_feature_um: 30.0,
        min_gap_um: 30.0,
        ..Rules::default()
    }
}

/// The design with a lens pupil about four pixels across, its edge still cutting pixels: the
/// pupil region stays small enough for KLayout's space check of one merged
/// chrome polygon with hundreds of holes (six pixels across took 35 of the test's 60 s there).
fn with_small_pupil(mut d: Design) -> Design {
    let pitch_um = d.opening.pitch_um + d.tiling.wiring_gap_um;
    let small = d.optics.focal_length_mm * 1000.0 / (4.0 * pitch_um);
    // Never a larger pupil than the design's own (the Fourier presets' is one pixel).
    d.optics.f_number = small.clamp(d.optics.f_number, 64.0);
    d
}

struct Case {
    label: String,
    file: PathBuf,
    deck: PathBuf,
    counts: [usize; 3],
    smallest: [Option<f64>; 2],
}

fn findings(report: &udc_studio::core::mask::drc::DrcReport) -> ([usize; 3], [Option<f64>; 2]) {
    let smallest = |k: ViolationKind| {
        report
            .violations
            .iter()
            .filter(|v| v.kind == k)
            .map(|v| v.value)
            .reduce(f64::min)
    };
    (
        [
            report.counts[ViolationKind::MinFeature as usize],
            report.counts[ViolationKind::MinGap as usize],
            report.corner_contacts,
        ],
        [
            smallest(ViolationKind::MinFeature),
            smallest(ViolationKind::MinGap),
        ],
    )
}

fn klayout(cases: &[Case], dir: &Path) -> Vec<serde_json::Value> {
    let list: Vec<[&str; 2]> = cases
        .iter()
        .map(|c| [c.file.to_str().unwrap(), c.deck.to_str().unwrap()])
        .collect();
    let list_path = dir.join("cases.json");
    std::fs::write(&list_path, serde_json::to_string(&list).unwrap()).unwrap();
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mask_check.py");
    let out = Command::new("python3")
        .args([script, "klayout-drc-batch", list_path.to_str().unwrap()])
        .output()
        .expect("python3 with klayout is required (.ci/test installs it)");
    assert!(
        out.status.success(),
        "mask_check.py klayout-drc-batch: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn the_written_check_equals_klayouts_for_every_preset_region_and_tone() {
    let dir = tempfile::tempdir().unwrap();
    let mut cases = Vec::new();
    for preset in PRESETS {
        let design = with_small_pupil(load_preset(preset.name).unwrap());
        let regions = [
            MaskRegion::PIXEL,
            MaskRegion::Block { cols: 3, rows: 3 },
            MaskRegion::Pupil,
        ];
        for region in regions {
            for tone in Tone::ALL {
                // The default everywhere; `cut` too where openings cross the pixel edges.
                let cuts = ["disc-lattice", "l2inv-random", "poled-336um", "l2-repeat"];
                let borders: &[BorderPolicy] = if cuts.contains(&preset.name) {
                    &[BorderPolicy::Margin, BorderPolicy::Cut]
                } else {
                    &[BorderPolicy::Margin]
                };
                for &border in borders {
                    let label = format!(
                        "{} {} {} {}",
                        preset.name,
                        region.label(),
                        tone.as_str(),
                        border.as_str()
                    );
                    let file = dir.path().join(format!("{}.gds", label.replace(' ', "-")));
                    let o = ExportOptions {
                        format: MaskFormat::Gds,
                        spec: MaskSpec {
                            region,
                            tone,
                            border,
                            ..MaskSpec::default()
                        },
                        rules: rules(),
                        deterministic: true,
                        ..ExportOptions::default()
                    };
                    let report = export_mask(&design, &o, &file, &Progress::new())
                        .unwrap_or_else(|e| panic!("{label}: {e}"));
                    let deck = file.with_extension("lydrc");
                    std::fs::write(&deck, drc_deck(&rules(), (1, 0), tone, &design.name)).unwrap();
                    // The file read back gives the export's own findings (a clear aperture
                    // drawn as chrome has nothing on the layer: said so, not judged clean).
                    let back = check_file(
                        &file,
                        (1, 0),
                        None,
                        &rules(),
                        ChecksumCheck::Verify,
                        &Progress::new(),
                    );
                    if report.stats.drawn_area_um2 == 0.0 {
                        let e = back.unwrap_err().to_string();
                        assert!(e.contains("layer 1"), "{label}: {e}");
                        assert!(report.drc.report.is_clean(), "{label}");
                    } else {
                        let (back, read_tone) = back.unwrap();
                        assert_eq!(read_tone, tone, "{label}");
                        assert_eq!(back, report.drc.report, "{label}: read back");
                    }
                    let (counts, smallest) = findings(&report.drc.report);
                    cases.push(Case {
                        label,
                        file,
                        deck,
                        counts,
                        smallest,
                    });
                }
            }
        }
    }
    let answers = klayout(&cases, dir.path());
    assert_eq!(answers.len(), cases.len());
    let mut with_findings = 0;
    for (case, k) in cases.iter().zip(&answers) {
        let count = |name: &str| k[name]["count"].as_u64().map_or(0, |v| v as usize);
        let least = |name: &str| {
            k[name]["distances_um"]
                .as_array()
                .and_then(|d| d.first())
                .and_then(serde_json::Value::as_f64)
        };
        let corners = k["corner_contact"]["points"].as_u64().unwrap() as usize;
        let theirs = [count("min_feature"), count("min_gap"), corners];
        assert_eq!(case.counts, theirs, "{}: ours vs KLayout's", case.label);
        assert_eq!(
            case.smallest,
            [least("min_feature"), least("min_gap")],
            "{}: narrowest findings",
            case.label
        );
        with_findings += usize::from(theirs.iter().any(|c| *c > 0));
    }
    // Enough of the matrix breaks a rule that the equality says something.
    assert!(
        with_findings > cases.len() / 3,
        "{with_findings} of {}",
        cases.len()
    );
}

#[test]
fn the_default_border_keeps_the_disc_lattice_clean_where_cut_leaves_slivers() {
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let strict = |border: &str, file: &str| {
        run_cli(&[
            "export",
            "--preset",
            "disc-lattice",
            "--format",
            "gds",
            "--region",
            "3x3",
            "--tone",
            "open",
            "--strict",
            "--min-feature-um",
            "20",
            "--border",
            border,
            "--out",
            &out(file),
        ])
    };
    // Cut: the 40-µm corner discs leave 16-µm slivers along the region's edge; nothing written.
    let (ok, stdout, stderr) = strict("cut", "cut.gds");
    assert!(!ok, "{stdout}");
    assert!(stderr.contains("nothing written"), "{stderr}");
    assert!(stdout.contains("16.000 µm"), "{stdout}");
    assert!(!dir.path().join("cut.gds").exists());
    // The default (margin) leaves them out: written, clean, and the report says what it did.
    let (ok, stdout, stderr) = strict("margin", "margin.gds");
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("12 openings cut by the edge, 12 left out"),
        "{stdout}"
    );
    assert!(
        stdout.contains("written geometry: no violation"),
        "{stdout}"
    );
    // Extend draws them whole, past the edge: also clean, and more open area than margin's.
    let (ok, stdout, stderr) = strict("extend", "extend.gds");
    assert!(ok, "{stderr}");
    assert!(stdout.contains("12 drawn whole"), "{stdout}");
    // `drc FILE` on each file says the same.
    let (ok, stdout, _) = run_cli(&["drc", &out("margin.gds"), "--min-feature-um", "20"]);
    assert!(ok && stdout.contains("no violation"), "{stdout}");
}

#[test]
fn drc_of_a_mask_file_refuses_what_it_cannot_judge() {
    let dir = tempfile::tempdir().unwrap();
    let gds = dir.path().join("m.gds");
    let g = gds.to_str().unwrap();
    let (ok, _, stderr) = run_cli(&[
        "export",
        "--preset",
        "toled-150dpi",
        "--format",
        "gds",
        "--region",
        "pixel",
        "--out",
        g,
    ]);
    assert!(ok, "{stderr}");
    // Nothing on the layer asked for.
    let (ok, _, stderr) = run_cli(&["drc", g, "--layer", "7"]);
    assert!(!ok && stderr.contains("7"), "{stderr}");
    // Design options make no sense on a file.
    let (ok, _, stderr) = run_cli(&["drc", g, "--pitch-um", "50"]);
    assert!(!ok && stderr.contains("mask file"), "{stderr}");
    // A changed byte fails the checksum beside it, unless told to go on.
    let mut bytes = std::fs::read(&gds).unwrap();
    let last = bytes.len() - 20;
    bytes[last] ^= 0x01;
    std::fs::write(&gds, &bytes).unwrap();
    let (ok, _, stderr) = run_cli(&["drc", g]);
    assert!(!ok && stderr.to_lowercase().contains("sha-256"), "{stderr}");
    // Mask flags on a design are refused.
    let (ok, _, stderr) = run_cli(&["drc", "--preset", "toled-150dpi", "--tone", "chrome"]);
    assert!(!ok && stderr.contains("mask files only"), "{stderr}");
}

#[test]
fn a_chrome_margin_frames_the_region_and_extend_is_refused_for_chrome() {
    let d = load_preset("disc-lattice").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let spec = |border, margin_um| MaskSpec {
        region: MaskRegion::Block { cols: 3, rows: 3 },
        tone: Tone::Chrome,
        border,
        margin_um,
        ..MaskSpec::default()
    };
    let o = |border, margin_um| ExportOptions {
        spec: spec(border, margin_um),
        ..ExportOptions::default()
    };
    let path = dir.path().join("c.gds");
    let margin = export_mask(&d, &o(BorderPolicy::Margin, 20.0), &path, &Progress::new()).unwrap();
    let drop = export_mask(&d, &o(BorderPolicy::Drop, 20.0), &path, &Progress::new()).unwrap();
    // The frame is a 20-µm ring of chrome around the 696-µm square region (corners included).
    let side = 3.0 * 232.0;
    let frame_um2 = (side + 40.0) * (side + 40.0) - side * side;
    let drawn = margin.stats.drawn_area_um2 - drop.stats.drawn_area_um2;
    assert!((drawn - frame_um2).abs() < 1e-6, "{drawn} vs {frame_um2}");
    // The region's clear area is the same either way: the frame lies outside it.
    assert_eq!(margin.stats.open_area_um2, drop.stats.open_area_um2);
    let err = export_mask(&d, &o(BorderPolicy::Extend, 20.0), &path, &Progress::new());
    assert!(err.unwrap_err().to_string().contains("chrome"));
    let err = export_mask(&d, &o(BorderPolicy::Margin, -1.0), &path, &Progress::new());
    assert!(err.unwrap_err().to_string().contains("margin"));
}

#[test]
fn a_display_sized_export_is_checked_as_a_design_and_says_so() {
    let d = load_preset("toled-150dpi").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let o = |cols| ExportOptions {
        format: MaskFormat::Oas,
        spec: MaskSpec {
            region: MaskRegion::Block { cols, rows: 600 },
            ..MaskSpec::default()
        },
        ..ExportOptions::default()
    };
    // 600 × 600 pixels of one 4-vertex slit: 1.44 M vertices, checked as written.
    let small = export_mask(&d, &o(600), &dir.path().join("s.oas"), &Progress::new()).unwrap();
    assert_eq!(small.drc.scope, CheckScope::Written);
    // 1000 × 600: 2.4 M, past the export's flat check: the design is checked, and named.
    let big = export_mask(&d, &o(1000), &dir.path().join("b.oas"), &Progress::new()).unwrap();
    assert_eq!(
        big.drc.scope,
        CheckScope::DesignOnly {
            vertices: 2_400_000
        }
    );
    assert!(big.drc.scope_line().contains("on the design only"));
    assert_eq!(
        big.drc.report.min_feature_um,
        small.drc.report.min_feature_um
    );
}
