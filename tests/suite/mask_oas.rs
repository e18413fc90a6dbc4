//! OASIS masks against independent readers: KLayout (its Python module) draws exactly what the
//! GDSII export draws (XOR area 0) and reports no warning, gdstk validates the CRC-32, a
//! display-sized random tiling is far smaller than its GDSII, and the studio's reader imports
//! both its own files and KLayout's (CBLOCK-compressed) rewrites of them. Needs python3 with
//! klayout and gdstk (`.ci/test` installs them).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::process::Command;

use udc_studio::core::Progress;
use udc_studio::core::design::{Design, TilingMode};
use udc_studio::core::mask::{BorderPolicy, MaskRegion, MaskSpec, Tone};
use udc_studio::io::design::presets::load_preset;
use udc_studio::io::error::{IoError, OasisError};
use udc_studio::io::mask::{
    ExportOptions, GdsCells, ImportOptions, MaskFormat, MaskReport, export_mask, import_mask,
};

/// Runs `tests/mask_check.py`; KLayout's warnings go to stderr, so stderr must stay empty.
fn check(args: &[&str]) -> serde_json::Value {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mask_check.py");
    let need = "python3 with klayout and gdstk is required (pip install klayout gdstk; \
                .ci/test installs them)";
    let out = Command::new("python3")
        .arg(script)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("{need}: cannot run python3: {e}"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "{need}. mask_check.py {args:?}:\n{stderr}"
    );
    assert!(
        stderr.trim().is_empty(),
        "KLayout warned on {args:?}:\n{stderr}"
    );
    serde_json::from_slice(&out.stdout).expect("mask_check.py prints JSON")
}

fn export(
    d: &Design,
    format: MaskFormat,
    region: MaskRegion,
    tone: Tone,
    path: &Path,
) -> MaskReport {
    let o = ExportOptions {
        format,
        spec: MaskSpec {
            region,
            tone,
            border: BorderPolicy::Cut,
            ..MaskSpec::default()
        },
        deterministic: true,
        ..ExportOptions::default()
    };
    export_mask(d, &o, path, &Progress::new()).unwrap()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// KLayout reads both files, sees one top cell, and their drawn layers XOR to nothing; the
/// area is the export's own open area.
fn assert_same_drawing(oas: &Path, gds: &Path, report: &MaskReport) {
    let k = check(&["klayout", s(oas), "1", "0", s(gds)]);
    assert_eq!(k["tops"].as_array().unwrap().len(), 1, "{k}");
    assert_eq!(k["xor_area_um2"].as_f64().unwrap(), 0.0, "{k}");
    let area = k["area_um2"].as_f64().unwrap();
    assert!(
        (area - report.stats.drawn_area_um2).abs() <= 1e-9 * report.stats.drawn_area_um2,
        "KLayout's area {area} µm² vs the export's {} µm²",
        report.stats.drawn_area_um2
    );
    assert!(
        k["texts"]
            .as_array()
            .unwrap()
            .iter()
            .any(|t| t.as_str().unwrap().starts_with("TONE=")),
        "{k}"
    );
    assert_eq!(check(&["oas-validate", s(oas)])["valid"], true);
}

#[test]
fn oas_random_tiling_draws_what_gds_draws() {
    let dir = tempfile::tempdir().unwrap();
    let d = load_preset("l2inv-random").unwrap();
    let region = MaskRegion::Block { cols: 40, rows: 30 };
    let (oas, gds) = (dir.path().join("m.oas"), dir.path().join("m.gds"));
    let r = export(&d, MaskFormat::Oas, region, Tone::Open, &oas);
    export(&d, MaskFormat::Gds, region, Tone::Open, &gds);
    assert_same_drawing(&oas, &gds, &r);
    // One placement per tile row and orientation; every tile covered.
    assert!(
        r.counts.arrays + r.counts.references <= 30 * 8,
        "{:?}",
        r.counts
    );
}

#[test]
fn oas_periodic_pupil_and_chrome_gap_draw_what_gds_draws() {
    let dir = tempfile::tempdir().unwrap();
    let mut d = load_preset("toled-150dpi").unwrap();
    d.tiling.wiring_gap_um = 8.0;
    for (k, (region, tone)) in [
        (MaskRegion::Pupil, Tone::Open),
        (MaskRegion::Block { cols: 7, rows: 5 }, Tone::Chrome),
        (MaskRegion::Block { cols: 1, rows: 1 }, Tone::Chrome),
    ]
    .into_iter()
    .enumerate()
    {
        let (oas, gds) = (
            dir.path().join(format!("m{k}.oas")),
            dir.path().join(format!("m{k}.gds")),
        );
        let r = export(&d, MaskFormat::Oas, region, tone, &oas);
        export(&d, MaskFormat::Gds, region, tone, &gds);
        assert_same_drawing(&oas, &gds, &r);
    }
}

#[test]
fn oas_per_orientation_cells_and_reflections_agree() {
    let dir = tempfile::tempdir().unwrap();
    let mut d = load_preset("l2-random").unwrap();
    d.tiling.mode = TilingMode::RandomD4;
    let (oas, gds) = (dir.path().join("p.oas"), dir.path().join("p.gds"));
    let o = |format| ExportOptions {
        format,
        gds_cells: GdsCells::PerOrientation,
        spec: MaskSpec {
            region: MaskRegion::Block { cols: 12, rows: 9 },
            border: BorderPolicy::Cut,
            ..MaskSpec::default()
        },
        deterministic: true,
        ..ExportOptions::default()
    };
    let r = export_mask(&d, &o(MaskFormat::Oas), &oas, &Progress::new()).unwrap();
    export_mask(&d, &o(MaskFormat::Gds), &gds, &Progress::new()).unwrap();
    assert_same_drawing(&oas, &gds, &r);
}

#[test]
fn oas_display_sized_random_tiling_is_far_smaller_than_gds() {
    // The goal: a 1080×2400 random tiling as OASIS at least 5× smaller than GDSII.
    let dir = tempfile::tempdir().unwrap();
    let d = load_preset("l2inv-random").unwrap();
    let region = MaskRegion::Block {
        cols: 1080,
        rows: 2400,
    };
    let (oas, gds) = (dir.path().join("big.oas"), dir.path().join("big.gds"));
    let ro = export(&d, MaskFormat::Oas, region, Tone::Open, &oas);
    let rg = export(&d, MaskFormat::Gds, region, Tone::Open, &gds);
    let (bo, bg) = (
        std::fs::metadata(&oas).unwrap().len(),
        std::fs::metadata(&gds).unwrap().len(),
    );
    assert_eq!(
        ro.counts.bytes, bo,
        "the report states the OASIS file's size"
    );
    assert!(bo * 5 <= bg, "OASIS {bo} B vs GDSII {bg} B");
    assert_eq!(ro.stats.tiles, 1080 * 2400);
    assert_eq!(check(&["oas-validate", s(&oas)])["valid"], true);
    // The estimate the export dialog shows is within a factor of 2 of the file.
    let est = udc_studio::io::mask::estimate(
        &udc_studio::io::mask::plan(&d, &ro.options).unwrap(),
        &ro.options,
    );
    assert!(
        est.bytes * 2 >= bo && est.bytes <= bo * 2,
        "estimate {} B vs file {bo} B",
        est.bytes
    );
    let _ = rg;
}

#[test]
fn oas_deterministic_exports_are_byte_identical() {
    // Same name in two folders: the notes name the sidecar file, so the names must match.
    let (x, y) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    let d = load_preset("l2inv-random").unwrap();
    let region = MaskRegion::Block { cols: 20, rows: 10 };
    let (a, b) = (x.path().join("m.oas"), y.path().join("m.oas"));
    export(&d, MaskFormat::Oas, region, Tone::Open, &a);
    export(&d, MaskFormat::Oas, region, Tone::Open, &b);
    let same = |a: &Path, b: &Path| std::fs::read(a).unwrap() == std::fs::read(b).unwrap();
    assert!(same(&a, &b), "two deterministic exports differ");
    let mut other = d.clone();
    other.tiling.seed += 1;
    export(&other, MaskFormat::Oas, region, Tone::Open, &b);
    assert!(!same(&a, &b), "another seed wrote the same file");
}

#[test]
fn oas_import_reads_ours_and_klayouts_rewrite_like_gds() {
    let dir = tempfile::tempdir().unwrap();
    let d = load_preset("l2inv-random").unwrap();
    let region = MaskRegion::Block { cols: 9, rows: 7 };
    let (oas, gds, kl) = (
        dir.path().join("m.oas"),
        dir.path().join("m.gds"),
        dir.path().join("kl.oas"),
    );
    export(&d, MaskFormat::Oas, region, Tone::Open, &oas);
    export(&d, MaskFormat::Gds, region, Tone::Open, &gds);
    // KLayout writes CBLOCKs, name tables and its own repetitions and modal variables.
    check(&["klayout-convert", s(&gds), s(&kl)]);
    assert_ne!(std::fs::read(&kl).unwrap(), std::fs::read(&oas).unwrap());
    let opts = ImportOptions {
        cell_um: d.opening.pitch_um / d.opening.cells.len() as f64,
        ..ImportOptions::default()
    };
    let want = import_mask(&gds, &opts).unwrap();
    for path in [&oas, &kl] {
        let got = import_mask(path, &opts).unwrap();
        assert_eq!(got.cells, want.cells, "{}", path.display());
        assert_eq!(got.tone, Tone::Open);
    }
    // And the CLI: the axis pixel back into a design, equal to the design's opening.
    let out = dir.path().join("back.json");
    let (ok, _, err) = crate::common::run_cli(&["import", s(&kl), "--out", s(&out)]);
    assert!(ok, "{err}");
    let back = udc_studio::io::design::file::load_design(&out).unwrap();
    let open = |c: &Vec<Vec<f64>>| c.iter().flatten().filter(|v| **v > 0.5).count();
    let cells = back.opening.cells;
    assert_eq!(open(&cells), open(&d.opening.cells));
}

#[test]
fn oas_damaged_files_are_refused_with_a_message() {
    let dir = tempfile::tempdir().unwrap();
    let d = load_preset("toled-150dpi").unwrap();
    let good = dir.path().join("g.oas");
    export(
        &d,
        MaskFormat::Oas,
        MaskRegion::Block { cols: 2, rows: 2 },
        Tone::Open,
        &good,
    );
    let bytes = std::fs::read(&good).unwrap();
    let opts = ImportOptions {
        cell_um: 1.0,
        ..ImportOptions::default()
    };
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("truncated", bytes[..bytes.len() / 2].to_vec(), "OASIS"),
        ("no header", b"hello".to_vec(), "not an OASIS file"),
        ("no end", bytes[..bytes.len() - 256].to_vec(), "END"),
        (
            "garbage",
            [
                &bytes[..13],
                &[
                    0x7f, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x7f,
                ][..],
            ]
            .concat(),
            "OASIS",
        ),
    ];
    for (what, data, needle) in cases {
        let p = dir.path().join(format!("{}.oas", what.replace(' ', "_")));
        std::fs::write(&p, data).unwrap();
        let e = import_mask(&p, &opts).expect_err(what).to_string();
        assert!(e.contains(needle), "{what}: {e}");
        assert!(
            e.contains(p.file_name().unwrap().to_str().unwrap()),
            "{what}: {e}"
        );
    }
}

#[test]
fn klayout_reads_every_export_without_a_warning() {
    use udc_studio::core::phase::PhaseDesign;
    use udc_studio::io::phase::export::{HeightFormat, HeightParams, write_height};
    let dir = tempfile::tempdir().unwrap();
    let random = load_preset("l2inv-random").unwrap();
    let mut gap = load_preset("toled-150dpi").unwrap();
    gap.tiling.wiring_gap_um = 8.0;
    let block = MaskRegion::Block { cols: 6, rows: 4 };
    let mut files = Vec::new();
    for (k, (d, format, region, tone)) in [
        (&random, MaskFormat::Gds, block, Tone::Open),
        (&random, MaskFormat::Oas, block, Tone::Open),
        (&random, MaskFormat::Dxf, block, Tone::Open),
        (&gap, MaskFormat::Gds, MaskRegion::Pupil, Tone::Chrome),
        (&gap, MaskFormat::Oas, MaskRegion::Pupil, Tone::Chrome),
        (&gap, MaskFormat::Dxf, MaskRegion::Pupil, Tone::Open),
    ]
    .into_iter()
    .enumerate()
    {
        let path = dir.path().join(format!("m{k}.{}", format.extension()));
        export(d, format, region, tone, &path);
        files.push(path);
    }
    let mut plate = PhaseDesign::thesis(168.0, 1.0);
    plate.height_step_um = Some(0.2);
    let params = HeightParams {
        sample_um: 0.5,
        rows: 4,
        length_um: 100.0,
        base_um: 5.0,
        deterministic: true,
        phase_min_feature_um: 0.0,
    };
    let phase = dir.path().join("plate.gds");
    write_height(HeightFormat::Gds, &plate, &phase, &params).unwrap();
    files.push(phase);
    for f in &files {
        // `check` fails on anything KLayout prints to stderr (its warnings go there).
        let k = check(&["klayout", s(f), "1", "0"]);
        assert_eq!(
            k["tops"].as_array().unwrap().len(),
            1,
            "{}: {k}",
            f.display()
        );
    }
}

#[test]
fn oas_frame_marks_and_label_match_gds() {
    use udc_studio::core::mask::FrameSpec;
    let dir = tempfile::tempdir().unwrap();
    let d = load_preset("l2inv-random").unwrap();
    let o = |format| ExportOptions {
        format,
        spec: MaskSpec {
            region: MaskRegion::Block { cols: 5, rows: 3 },
            border: BorderPolicy::Cut,
            ..MaskSpec::default()
        },
        frame: FrameSpec {
            frame: true,
            marks: true,
            label: true,
            ..FrameSpec::default()
        },
        deterministic: true,
        ..ExportOptions::default()
    };
    let (oas, gds) = (dir.path().join("f.oas"), dir.path().join("f.gds"));
    export_mask(&d, &o(MaskFormat::Oas), &oas, &Progress::new()).unwrap();
    export_mask(&d, &o(MaskFormat::Gds), &gds, &Progress::new()).unwrap();
    for layer in ["10", "11"] {
        let k = check(&["klayout", s(&oas), layer, "0", s(&gds)]);
        assert!(
            k["area_um2"].as_f64().unwrap() > 0.0,
            "nothing on {layer}/0: {k}"
        );
        assert_eq!(k["xor_area_um2"].as_f64().unwrap(), 0.0, "{layer}/0: {k}");
    }
    let k = check(&["klayout", s(&oas), "1", "0"]);
    let texts: Vec<&str> = k["texts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t.as_str().unwrap())
        .collect();
    assert!(
        texts
            .iter()
            .any(|t| t.starts_with("UDC STUDIO") && t.contains("2000-01-01")),
        "{texts:?}"
    );
}

#[test]
fn oas_a_cblock_inside_a_cblock_is_refused() {
    use std::io::Write;
    // SEMI P39 forbids nesting; a crafted file could otherwise recurse without bound.
    let deflate = |data: &[u8]| {
        let mut e = flate2::write::DeflateEncoder::new(Vec::new(), flate2::Compression::default());
        e.write_all(data).unwrap();
        e.finish().unwrap()
    };
    let cblock = |inner: &[u8]| {
        let packed = deflate(inner);
        let mut out = vec![34, 0, inner.len() as u8, packed.len() as u8];
        assert!(inner.len() < 128 && packed.len() < 128);
        out.extend_from_slice(&packed);
        out
    };
    let mut file = b"%SEMI-OASIS\r\n".to_vec();
    // START: version "1.0", unit 1000 (real type 0), offset-flag 0, twelve zero table offsets.
    file.extend_from_slice(&[1, 3, b'1', b'.', b'0', 0, 0xe8, 0x07, 0]);
    file.extend_from_slice(&[0; 12]);
    file.extend_from_slice(&cblock(&cblock(&[0, 0, 0])));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("nested.oas");
    std::fs::write(&path, file).unwrap();
    let opts = ImportOptions {
        cell_um: 1.0,
        ..ImportOptions::default()
    };
    let e = import_mask(&path, &opts).unwrap_err();
    assert!(e.to_string().contains("CBLOCK inside a CBLOCK"), "{e}");
    // The outer CBLOCK follows the 21-byte START; the inner one opens its inflated bytes.
    let IoError::Oasis {
        error: OasisError::Unreadable(record),
        ..
    } = &e
    else {
        panic!("{e:?}")
    };
    let OasisError::Record {
        id: 34,
        byte: 21,
        error: inner,
    } = &**record
    else {
        panic!("{record:?}")
    };
    let OasisError::Record {
        id: 34,
        byte: 0,
        error: refused,
    } = &**inner
    else {
        panic!("{inner:?}")
    };
    assert!(matches!(**refused, OasisError::NestedCblock), "{refused:?}");
}
