//! Mask files against independent readers: gdstk (GDSII) and ezdxf (DXF) through
//! `tests/mask_check.py`, and the studio's own importer for round trips. Needs python3 with
//! gdstk and ezdxf (`pip install gdstk ezdxf`; CI installs them); without them these tests fail.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};
use std::process::Command;

use rand::{Rng, SeedableRng};
use udc_studio::core::Progress;
use udc_studio::core::design::{Design, Opening, TilingMode};
use udc_studio::core::display::tiling::tile_orientation;
use udc_studio::core::mask::{BorderPolicy, MaskLayout, MaskRegion, MaskSpec, Tone};
use udc_studio::io::mask::{
    ExportOptions, GdsCells, ImportOptions, ImportWindow, MaskFormat, MaskReport, PngBits,
    estimate, export_mask, import_mask, plan, sidecar_path,
};

const N: usize = 8;
const CELL_UM: f64 = 8.0;

/// An 8×8 pattern without any D4 symmetry (so every orientation is distinguishable), 64 µm
/// pitch (8 µm cells: every coordinate is a whole number of nanometres).
fn design(mode: TilingMode, seed: u64, gap_um: f64) -> Design {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
    let mut cells: Vec<Vec<f64>> = (0..N)
        .map(|_| {
            (0..N)
                .map(|_| f64::from(u8::from(rng.random::<f64>() < 0.45)))
                .collect()
        })
        .collect();
    cells[0][0] = 1.0;
    cells[0][1] = 1.0;
    cells[1][0] = 0.0;
    let mut d = Design::default_toled();
    d.name = "mask test".into();
    d.opening = Opening {
        pitch_um: N as f64 * CELL_UM,
        cells,
        polygons: Vec::new(),
    };
    d.tiling.mode = mode;
    d.tiling.seed = seed;
    d.tiling.origin_offset_cells = [3.0, 3.0];
    d.tiling.wiring_gap_um = gap_um;
    d
}

fn options(format: MaskFormat, region: MaskRegion, tone: Tone) -> ExportOptions {
    ExportOptions {
        format,
        spec: MaskSpec {
            region,
            tone,
            border: BorderPolicy::Cut,
            ..MaskSpec::default()
        },
        // Fixed timestamps: reruns write the same bytes.
        deterministic: true,
        ..ExportOptions::default()
    }
}

fn export(d: &Design, o: &ExportOptions, path: &Path) -> MaskReport {
    export_mask(d, o, path, &Progress::new()).unwrap()
}

/// Runs the independent reader; fails loudly when python3, gdstk or ezdxf is missing.
fn python_check(args: &[&str]) -> serde_json::Value {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mask_check.py");
    let need = "python3 with gdstk and ezdxf is required for the mask tests \
                (pip install gdstk ezdxf; .ci/run installs them)";
    let out = Command::new("python3")
        .arg(script)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("{need}: cannot run python3: {e}"));
    assert!(
        out.status.success(),
        "{need}. mask_check.py {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("mask_check.py prints JSON")
}

fn num(v: &serde_json::Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing in {v}"))
}

/// The display's cells over a block region, from `tile_orientation` and `D4::apply`: what the
/// simulation sees, so what a mask must hold.
fn expected_cells(d: &Design, cols: u32, rows: u32) -> (Vec<Vec<f64>>, usize) {
    let (tx0, ty0) = (-i64::from(cols / 2), -i64::from(rows / 2));
    let mut out = vec![vec![0.0; cols as usize * N]; rows as usize * N];
    let mut used = std::collections::HashSet::new();
    for j in 0..rows as usize {
        for i in 0..cols as usize {
            let g = tile_orientation(d.tiling.mode, d.tiling.seed, tx0 + i as i64, ty0 + j as i64);
            used.insert(g);
            let tile = g.apply(&d.opening.cells);
            for r in 0..N {
                for c in 0..N {
                    out[j * N + r][i * N + c] = tile[r][c];
                }
            }
        }
    }
    (out, used.len())
}

fn block_window(d: &Design, cols: u32, rows: u32) -> ImportWindow {
    let spec = MaskSpec {
        region: MaskRegion::Block { cols, rows },
        border: BorderPolicy::Cut,
        ..MaskSpec::default()
    };
    let layout = MaskLayout::new(d, &spec).unwrap();
    let [x, y] = layout.tile_corner_nm(-i64::from(cols / 2), -i64::from(rows / 2));
    ImportWindow {
        left_um: x as f64 * 1e-3,
        top_um: y as f64 * 1e-3,
        cols: cols as usize * N,
        rows: rows as usize * N,
    }
}

fn round_trip(d: &Design, o: &ExportOptions, path: &Path, cols: u32, rows: u32) {
    export(d, o, path);
    let imported = import_mask(
        path,
        &ImportOptions {
            cell_um: CELL_UM,
            layer: o.layer,
            datatype: o.datatype,
            layer_name: None,
            cell: None,
            window: Some(block_window(d, cols, rows)),
            tone: None,
            checksum: udc_studio::io::mask::ChecksumCheck::Verify,
        },
    )
    .unwrap();
    assert_eq!(
        imported.tone, o.spec.tone,
        "the tone is read back from the file"
    );
    let (want, _) = expected_cells(d, cols, rows);
    assert!(
        imported.cells == want,
        "{:?} {:?} {:?}: the cells read back differ",
        o.format,
        o.gds_cells,
        d.tiling.mode
    );
}

const MODES: [(TilingMode, u64); 3] = [
    (TilingMode::Repeat, 0),
    (TilingMode::RandomD4, 5),
    (TilingMode::Random4, 3),
];

#[test]
fn gds_round_trip_restores_every_tile_in_every_orientation() {
    let dir = tempfile::tempdir().unwrap();
    let (_, used) = expected_cells(&design(TilingMode::RandomD4, 5, 0.0), 6, 5);
    assert_eq!(used, 8, "the random-d4 case must use all 8 orientations");
    let (_, used) = expected_cells(&design(TilingMode::Random4, 3, 0.0), 6, 5);
    assert_eq!(used, 4);
    for (mode, seed) in MODES {
        for cells in [GdsCells::Strans, GdsCells::PerOrientation] {
            for tone in Tone::ALL {
                let d = design(mode, seed, 0.0);
                let mut o = options(
                    MaskFormat::Gds,
                    MaskRegion::Block { cols: 6, rows: 5 },
                    tone,
                );
                o.gds_cells = cells;
                round_trip(&d, &o, &dir.path().join("m.gds"), 6, 5);
            }
        }
    }
}

#[test]
fn dxf_round_trip_restores_every_tile_in_every_orientation() {
    let dir = tempfile::tempdir().unwrap();
    for (mode, seed) in MODES {
        for tone in Tone::ALL {
            let d = design(mode, seed, 0.0);
            let o = options(
                MaskFormat::Dxf,
                MaskRegion::Block { cols: 6, rows: 5 },
                tone,
            );
            round_trip(&d, &o, &dir.path().join("m.dxf"), 6, 5);
        }
    }
}

#[test]
fn gdstk_places_every_cell_where_d4_source_says() {
    // gdstk applies the references' reflection and rotation itself: the STRANS mapping is
    // checked by a reader that shares no code with the writer.
    let dir = tempfile::tempdir().unwrap();
    let d = design(TilingMode::RandomD4, 5, 0.0);
    let (want, used) = expected_cells(&d, 6, 5);
    assert_eq!(used, 8);
    let w = block_window(&d, 6, 5);
    let centres: Vec<[f64; 2]> = (0..w.rows)
        .flat_map(|r| {
            (0..w.cols).map(move |c| {
                [
                    w.left_um + (c as f64 + 0.5) * CELL_UM,
                    w.top_um - (r as f64 + 0.5) * CELL_UM,
                ]
            })
        })
        .collect();
    let points = dir.path().join("points.json");
    std::fs::write(&points, serde_json::to_string(&centres).unwrap()).unwrap();
    for cells in [GdsCells::Strans, GdsCells::PerOrientation] {
        let mut o = options(
            MaskFormat::Gds,
            MaskRegion::Block { cols: 6, rows: 5 },
            Tone::Open,
        );
        o.gds_cells = cells;
        let path = dir.path().join("m.gds");
        let report = export(&d, &o, &path);
        assert_eq!(report.counts.references, 30);
        let v = python_check(&["gds", s(&path), "1", "0", s(&points)]);
        let inside = v["inside"].as_array().unwrap();
        for (k, hit) in inside.iter().enumerate() {
            let (r, c) = (k / w.cols, k % w.cols);
            assert_eq!(
                hit.as_bool().unwrap(),
                want[r][c] == 1.0,
                "{cells:?}: cell ({r}, {c}) of the display"
            );
        }
    }
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Drawn area the design implies: open cells × cell² per pixel (open tone), or the rest of
/// each period square (chrome tone).
fn expected_drawn_um2(d: &Design, tiles: u64, tone: Tone) -> f64 {
    let open_cells = d
        .opening
        .cells
        .iter()
        .flatten()
        .filter(|v| **v >= 0.5)
        .count() as f64;
    let open = open_cells * CELL_UM * CELL_UM;
    let period = d.opening.pitch_um + d.tiling.wiring_gap_um;
    tiles as f64
        * match tone {
            Tone::Open => open,
            Tone::Chrome => period * period - open,
        }
}

fn assert_rel(got: f64, want: f64, what: &str) {
    assert!(
        (got - want).abs() <= 1e-6 * want,
        "{what}: {got} µm² read back, {want} µm² expected"
    );
}

#[test]
fn gdstk_measures_the_open_fraction_times_the_region_area() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (TilingMode::Repeat, 0.0, MaskRegion::PIXEL, Tone::Open),
        (TilingMode::RandomD4, 4.0, MaskRegion::Pupil, Tone::Open),
        (
            TilingMode::Random4,
            4.0,
            MaskRegion::Block { cols: 7, rows: 5 },
            Tone::Chrome,
        ),
        (TilingMode::Repeat, 4.0, MaskRegion::Pupil, Tone::Chrome),
        (
            TilingMode::Repeat,
            0.0,
            MaskRegion::Block { cols: 40, rows: 30 },
            Tone::Open,
        ),
    ];
    for (mode, gap, region, tone) in cases {
        let d = design(mode, 9, gap);
        let path = dir.path().join("a.gds");
        let o = options(MaskFormat::Gds, region, tone);
        let report = export(&d, &o, &path);
        let v = python_check(&["gds", s(&path), "1", "0"]);
        let what = format!("{mode:?} {region:?} {tone:?}");
        // The dialog's estimate is what gets written.
        // Resolved as the export resolves it: the derived top cell name is part of the size.
        let est = estimate(&plan(&d, &o).unwrap(), &o.resolved(&d).unwrap());
        let c = report.counts;
        assert_eq!(
            (est.polygons, est.vertices, est.references, est.arrays),
            (c.polygons, c.vertices, c.references, c.arrays),
            "{what}"
        );
        let size = std::fs::metadata(&path).unwrap().len();
        assert_eq!(c.bytes, size, "{what}");
        assert!(
            (est.bytes as f64 - size as f64).abs() < 0.1 * size as f64 + 400.0,
            "{what}: estimated {} bytes, wrote {size}",
            est.bytes
        );
        assert_eq!(num(&v, "user_unit_m"), 1e-6, "{what}");
        assert_eq!(num(&v, "db_unit_m"), 1e-9, "{what}");
        let want = expected_drawn_um2(&d, report.stats.tiles, tone);
        assert_rel(num(&v, "area_um2"), want, &what);
        assert_rel(report.stats.drawn_area_um2, want, &what);
        // Open area = open fraction × region area, whatever the tone.
        let open = report.stats.open_fraction() * report.stats.region_area_um2;
        assert_rel(
            open,
            expected_drawn_um2(&d, report.stats.tiles, Tone::Open),
            &what,
        );
        let tone_note = format!("TONE={}", tone.as_str().to_uppercase());
        let texts = v["texts"].as_array().unwrap();
        assert!(
            texts
                .iter()
                .any(|t| t.as_str().unwrap().starts_with(&tone_note)),
            "{what}: {texts:?}"
        );
        let refs = num(&v, "references") as u64;
        let arrays = num(&v, "arrays") as u64;
        assert_eq!(refs, report.counts.references, "{what}");
        assert_eq!(arrays, report.counts.arrays, "{what}");
        if mode.is_random() {
            assert!(
                refs >= report.stats.tiles,
                "{what}: one reference per pixel"
            );
        } else if report.stats.tiles > 1 {
            assert!(
                refs < report.stats.tiles / 4,
                "{what}: periodic tilings use arrays"
            );
            assert!(arrays >= 1, "{what}");
        }
        let sidecar: Design =
            udc_studio::io::design::file::load_design(&sidecar_path(&path)).unwrap();
        assert_eq!(sidecar, d, "{what}: the sidecar holds the design");
    }
}

#[test]
fn ezdxf_measures_the_same_area_in_micrometres() {
    let dir = tempfile::tempdir().unwrap();
    for (mode, gap, region, tone) in [
        (
            TilingMode::RandomD4,
            0.0,
            MaskRegion::Block { cols: 5, rows: 4 },
            Tone::Open,
        ),
        (TilingMode::Random4, 4.0, MaskRegion::Pupil, Tone::Chrome),
    ] {
        let d = design(mode, 2, gap);
        let path = dir.path().join("a.dxf");
        let report = export(&d, &options(MaskFormat::Dxf, region, tone), &path);
        let v = python_check(&["dxf", s(&path), "L1D0"]);
        assert_eq!(v["version"], "AC1015", "R2000");
        assert_eq!(num(&v, "insunits"), 13.0, "micrometres");
        assert_eq!(v["closed"], true);
        assert_eq!(num(&v, "polygons") as u64, report.counts.polygons);
        let want = expected_drawn_um2(&d, report.stats.tiles, tone);
        assert_rel(num(&v, "area_um2"), want, &format!("{mode:?} {tone:?}"));
        let texts = v["texts"].to_string();
        assert!(texts.contains(&format!("TONE={}", tone.as_str().to_uppercase())));
    }
}

/// Shoelace area of every `<path d="M x y L x y … Z"/>` in an SVG, in viewBox units (µm).
fn svg_area_um2(text: &str) -> (f64, usize) {
    let mut total = 0.0;
    let mut count = 0;
    for part in text.split("<path d=\"M").skip(1) {
        let d = part.split('Z').next().unwrap();
        let pts: Vec<[f64; 2]> = d
            .split(" L")
            .map(|xy| {
                let mut it = xy.split_whitespace().map(|v| v.parse::<f64>().unwrap());
                [it.next().unwrap(), it.next().unwrap()]
            })
            .collect();
        let n = pts.len();
        let twice: f64 = (0..n)
            .map(|i| pts[i][0] * pts[(i + 1) % n][1] - pts[(i + 1) % n][0] * pts[i][1])
            .sum();
        total += twice.abs() / 2.0;
        count += 1;
    }
    (total, count)
}

#[test]
fn svg_and_png_draw_the_same_area() {
    let dir = tempfile::tempdir().unwrap();
    for tone in Tone::ALL {
        let d = design(TilingMode::RandomD4, 4, 8.0);
        let region = MaskRegion::Block { cols: 4, rows: 3 };
        let want = expected_drawn_um2(&d, 12, tone);
        let svg = dir.path().join("a.svg");
        let report = export(&d, &options(MaskFormat::Svg, region, tone), &svg);
        let text = std::fs::read_to_string(&svg).unwrap();
        assert!(text.contains("viewBox=\""), "µm user units");
        assert!(text.contains(tone.meaning().to_uppercase().as_str()));
        let (area, count) = svg_area_um2(&text);
        assert_eq!(count as u64, report.counts.polygons);
        assert_rel(area, want, "SVG");
        // 1 µm pixels on a 1 µm-aligned region: each pixel is wholly drawn or not.
        for bits in [PngBits::One, PngBits::Eight] {
            let png = dir.path().join("a.png");
            let mut o = options(MaskFormat::Png, region, tone);
            o.png_bits = bits;
            export(&d, &o, &png);
            let img = image::open(&png).unwrap().to_luma8();
            assert_eq!(img.width(), 4 * 72);
            assert_eq!(img.height(), 3 * 72);
            let drawn: f64 = img.pixels().map(|p| f64::from(p.0[0]) / 255.0).sum();
            assert_rel(drawn, want, &format!("PNG {bits:?}"));
        }
    }
}

#[test]
fn split_polygons_stay_under_the_limit_in_the_file() {
    // A comb: the spine and 4 teeth make one polygon of 16 vertices; a limit of 8 splits it.
    let dir = tempfile::tempdir().unwrap();
    let mut d = design(TilingMode::Repeat, 0, 0.0);
    d.opening.cells = (0..N)
        .map(|r| {
            (0..N)
                .map(|c| f64::from(u8::from(r == 7 || c % 2 == 0)))
                .collect()
        })
        .collect();
    let path = dir.path().join("comb.gds");
    let mut o = options(MaskFormat::Gds, MaskRegion::PIXEL, Tone::Open);
    let whole = export(&d, &o, &path);
    assert_eq!(whole.counts.polygons, 1);
    o.spec.max_vertices = 8;
    let report = export(&d, &o, &path);
    assert!(report.counts.polygons > 1);
    let v = python_check(&["gds", s(&path), "1", "0"]);
    assert!(num(&v, "max_vertices") <= 8.0, "{v}");
    assert_rel(
        num(&v, "area_um2"),
        expected_drawn_um2(&d, 1, Tone::Open),
        "split comb",
    );
}

#[test]
fn a_cancelled_export_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("never.gds");
    let progress = Progress::new();
    progress.cancel();
    let d = design(TilingMode::RandomD4, 1, 0.0);
    let o = options(
        MaskFormat::Gds,
        MaskRegion::Block { cols: 50, rows: 50 },
        Tone::Open,
    );
    let e = export_mask(&d, &o, &path, &progress).unwrap_err();
    assert_eq!(e.to_string(), "cancelled");
    let left: Vec<PathBuf> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

use crate::common::run_cli as run;

#[test]
fn cli_export_prints_the_summary_and_writes_the_sidecar() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("toled.gds");
    let (ok, stdout, stderr) = run(&[
        "export",
        "--preset",
        "toled-150dpi",
        "--tiling",
        "random-d4",
        "--seed",
        "4",
        "--format",
        "gds",
        "--region",
        "pupil",
        "--tone",
        "chrome",
        "--out",
        s(&out),
    ]);
    assert!(ok, "{stderr}");
    for needle in [
        "polygons:",
        "references:",
        "open area:",
        "LTR",
        "drawn = chrome (dark)",
    ] {
        assert!(stdout.contains(needle), "missing {needle} in\n{stdout}");
    }
    let v = python_check(&["gds", s(&out), "1", "0"]);
    let refs = num(&v, "references") as u64;
    assert!(
        stdout.contains(&format!("references: {refs} single")),
        "{stdout}"
    );
    let d = udc_studio::io::design::file::load_design(&sidecar_path(&out)).unwrap();
    assert_eq!(d.tiling.mode, TilingMode::RandomD4);
    assert_eq!(d.tiling.seed, 4);
}

#[test]
fn cli_export_rejects_bad_input_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let black = dir.path().join("black.png");
    image::GrayImage::new(6, 6).save(&black).unwrap();
    let out = dir.path().join("x.gds");
    let base = ["export", "--format", "gds", "--out", s(&out)];
    for (extra, needle) in [
        (
            vec!["--pattern", s(&black), "--region", "pixel"],
            "no open cell",
        ),
        (
            vec!["--pitch-um", "0", "--region", "pixel"],
            "--pitch-um: must be a positive",
        ),
        (vec!["--region", "100000x100000"], "region too large"),
        (vec!["--region", "30000x20"], "32-bit"),
        (vec!["--region", "0x4"], "empty"),
        (vec!["--region", "pixel", "--tone", "grey"], "grey"),
        (
            vec!["--region", "pixel", "--top-cell", "bad name"],
            "top cell",
        ),
    ] {
        let args: Vec<&str> = base.iter().copied().chain(extra).collect();
        let (ok, stdout, stderr) = run(&args);
        assert!(!ok, "{args:?} must fail");
        assert!(stdout.is_empty(), "{args:?} printed {stdout}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        // clap adds a "--help" hint line to its own parse errors.
        if !stderr.contains("--help") {
            assert_eq!(stderr.trim().lines().count(), 1, "{args:?}: {stderr}");
        }
        assert!(!out.exists(), "{args:?} left a file");
    }
}

#[test]
fn d4_orientations_have_distinct_gds_cells() {
    // Per-orientation mode writes one cell per orientation used (plus the top cell).
    let dir = tempfile::tempdir().unwrap();
    let d = design(TilingMode::RandomD4, 5, 0.0);
    let mut o = options(
        MaskFormat::Gds,
        MaskRegion::Block { cols: 6, rows: 5 },
        Tone::Open,
    );
    o.gds_cells = GdsCells::PerOrientation;
    let path = dir.path().join("cells.gds");
    export(&d, &o, &path);
    let v = python_check(&["gds", s(&path), "1", "0"]);
    assert_eq!(num(&v, "cells"), 9.0);
}

/// What the studio's File → Import opening does with a mask: the axis pixel comes back as the
/// design's own opening, whatever orientation that pixel has in the tiling.
#[test]
fn an_exported_pixel_imports_back_as_the_opening() {
    let dir = tempfile::tempdir().unwrap();
    for (mode, seeds) in [
        (TilingMode::Repeat, 0..1u64),
        (TilingMode::RandomD4, 0..12),
        (TilingMode::Random4, 0..6),
    ] {
        for seed in seeds {
            let d = design(mode, seed, 0.0);
            for format in [MaskFormat::Gds, MaskFormat::Dxf] {
                let path = dir
                    .path()
                    .join(format!("pixel-{seed}.{}", format.extension()));
                export(
                    &d,
                    &options(
                        format,
                        udc_studio::core::mask::MaskRegion::PIXEL,
                        Tone::Open,
                    ),
                    &path,
                );
                let cells = udc_studio::io::mask::import_opening(&path, &d).unwrap();
                assert_eq!(cells, d.opening.cells, "{mode:?} seed {seed} {format:?}");
            }
        }
    }
}
