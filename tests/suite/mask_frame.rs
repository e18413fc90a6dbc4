//! The optional die frame, alignment marks and label of a mask export: read back by the
//! independent readers (gdstk, ezdxf through `tests/mask_check.py`), on their own layers, outside
//! the active area, byte-identical when deterministic, absent unless asked for, and bad sizes
//! refused by the CLI with a message naming the option.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::process::Command;

use serde_json::Value;
use udc_studio::core::Progress;
use udc_studio::core::design::{Design, Opening, TilingMode};
use udc_studio::core::mask::{BorderPolicy, FrameSpec, MaskRegion, MaskSpec};
use udc_studio::io::fab::LayerMap;
use udc_studio::io::mask::{
    ExportOptions, MaskFormat, MaskReport, export_mask, plan, region_bbox_nm,
};

use crate::common::Reach;
use crate::common::run_cli;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs the independent reader; fails loudly when python3, gdstk or ezdxf is missing.
fn python_check(args: &[&str]) -> Value {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mask_check.py");
    let out = Command::new("python3")
        .arg(script)
        .args(args)
        .output()
        .expect("python3 with gdstk and ezdxf is required (.ci/test installs them)");
    assert!(
        out.status.success(),
        "mask_check.py {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("mask_check.py prints JSON")
}

/// A 6×6-cell opening in a 48 µm pixel, random D4 tiling (references with STRANS).
fn design() -> Design {
    let mut d = Design::default_toled();
    d.name = "frame test".into();
    d.opening = Opening {
        pitch_um: 48.0,
        cells: (0..6)
            .map(|i| {
                (0..6)
                    .map(|j| f64::from(u8::from((i + 2 * j) % 3 == 0)))
                    .collect()
            })
            .collect(),
        polygons: Vec::new(),
    };
    d.tiling.mode = TilingMode::RandomD4;
    d.tiling.seed = 9;
    d
}

fn options(format: MaskFormat, frame: FrameSpec) -> ExportOptions {
    ExportOptions {
        format,
        spec: MaskSpec {
            region: MaskRegion::Block { cols: 3, rows: 2 },
            grid_nm: 5,
            border: BorderPolicy::Cut,
            ..MaskSpec::default()
        },
        deterministic: true,
        frame,
        ..ExportOptions::default()
    }
}

fn everything() -> FrameSpec {
    FrameSpec {
        frame: true,
        marks: true,
        label: true,
        ..FrameSpec::default()
    }
}

fn export(d: &Design, o: &ExportOptions, path: &Path) -> MaskReport {
    export_mask(d, o, path, &Progress::new()).unwrap()
}

/// The region's bounding box in µm.
fn region_um(d: &Design, o: &ExportOptions) -> [f64; 4] {
    region_bbox_nm(&plan(d, o).unwrap()).map(|v| v as f64 / 1000.0)
}

fn assert_outside(bboxes: &Value, r: [f64; 4], what: &str) {
    for b in bboxes.as_array().unwrap() {
        let b: Vec<f64> = b
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert!(
            b[2] < r[0] || b[0] > r[2] || b[3] < r[1] || b[1] > r[3],
            "{what} {b:?} overlaps the region {r:?}"
        );
    }
}

/// Frame ring area for a region `r` (µm), margin `m` and width `w`.
fn ring_area(r: [f64; 4], m: f64, w: f64) -> f64 {
    let (wi, hi) = (r[2] - r[0] + 2.0 * m, r[3] - r[1] + 2.0 * m);
    (wi + 2.0 * w) * (hi + 2.0 * w) - wi * hi
}

#[test]
fn gds_frame_marks_and_label_read_back_by_gdstk() {
    let dir = tempfile::tempdir().unwrap();
    let d = design();
    let o = options(MaskFormat::Gds, everything());
    let path = dir.path().join("f.gds");
    export(&d, &o, &path);
    let r = region_um(&d, &o);
    let v = python_check(&["gds-layers", s(&path)]);
    let layers = &v["layers"];
    let frame = &layers["10/0"];
    assert_eq!(frame["polygons"], 4);
    let area = frame["area_um2"].as_f64().unwrap();
    assert!(
        (area - ring_area(r, 50.0, 10.0)).abs() < 1e-6,
        "{area} vs {r:?}"
    );
    let marks = &layers["11/0"];
    assert_eq!(marks["polygons"], 4);
    // 100 µm crosses with 10 µm arms: 2·100·10 − 10² each.
    assert!((marks["area_um2"].as_f64().unwrap() - 4.0 * 1900.0).abs() < 1e-6);
    assert_outside(&frame["bboxes"], r, "frame");
    assert_outside(&marks["bboxes"], r, "mark");
    // The openings are what they were without a frame.
    let plain = dir.path().join("plain.gds");
    export(&d, &options(MaskFormat::Gds, FrameSpec::default()), &plain);
    let p = python_check(&["gds-layers", s(&plain)]);
    assert_eq!(p["layers"]["1/0"]["area_um2"], layers["1/0"]["area_um2"]);
    assert!(p["layers"].get("10/0").is_none() && p["layers"].get("11/0").is_none());
    let labels: Vec<&Value> = v["texts"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|t| t["layer"] == "12/0")
        .collect();
    assert_eq!(labels.len(), 1, "{v}");
    assert_eq!(
        labels[0]["text"],
        "UDC STUDIO frame test 2000-01-01 SCALE 1 UM = 1000 DBU GRID 5 NM"
    );
    let at = labels[0]["at"].as_array().unwrap();
    assert!(at[1].as_f64().unwrap() + 20.0 < r[1], "label at {at:?}");
    let map = std::fs::read_to_string(dir.path().join("f.gds.layers.txt")).unwrap();
    let map = LayerMap::parse(&map).unwrap();
    assert_eq!(map.get("frame"), Some((10, 0)));
    assert_eq!(map.get("marks"), Some((11, 0)));
    assert_eq!(map.get("label"), Some((12, 0)));
    let plain_map = std::fs::read_to_string(dir.path().join("plain.gds.layers.txt")).unwrap();
    assert!(!plain_map.contains("frame"), "{plain_map}");
}

#[test]
fn dxf_frame_layers_read_back_by_ezdxf_without_repair() {
    let dir = tempfile::tempdir().unwrap();
    let d = design();
    let o = options(MaskFormat::Dxf, everything());
    let path = dir.path().join("f.dxf");
    export(&d, &o, &path);
    let r = region_um(&d, &o);
    let v = python_check(&["dxf-layers", s(&path)]);
    let table: Vec<&str> = v["layer_table"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap())
        .collect();
    for name in ["FRAME", "MARKS", "LABEL"] {
        assert!(table.contains(&name), "{table:?}");
    }
    let area = v["layers"]["FRAME"]["area_um2"].as_f64().unwrap();
    assert!((area - ring_area(r, 50.0, 10.0)).abs() < 1e-6);
    assert_eq!(v["layers"]["MARKS"]["polygons"], 4);
    assert_outside(&v["layers"]["FRAME"]["bboxes"], r, "frame");
    assert_outside(&v["layers"]["MARKS"]["bboxes"], r, "mark");
    let label = v["texts"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["layer"] == "LABEL")
        .expect("a TEXT on LABEL");
    assert_eq!(label["height"], 20.0);
    assert!(
        label["text"]
            .as_str()
            .unwrap()
            .contains("frame test 2000-01-01")
    );
    let audit = python_check(&["dxf-audit", s(&path)]);
    assert_eq!(audit["errors"], serde_json::json!([]), "{audit}");
    assert_eq!(audit["fixes"], serde_json::json!([]), "{audit}");
    // The header's extents cover the marks, the outermost polylines.
    assert_eq!(
        audit["extmin"].as_array().unwrap()[..],
        audit["bbox"].as_array().unwrap()[..2]
    );
    let marks = &v["layers"]["MARKS"]["bboxes"];
    let min_x = marks
        .as_array()
        .unwrap()
        .iter()
        .map(|b| b[0].as_f64().unwrap())
        .fold(f64::INFINITY, f64::min);
    assert_eq!(audit["extmin"][0].as_f64().unwrap(), min_x);
}

#[test]
fn deterministic_exports_with_a_label_are_byte_identical() {
    let dir = tempfile::tempdir().unwrap();
    let d = design();
    for format in [MaskFormat::Gds, MaskFormat::Dxf, MaskFormat::Svg] {
        let o = options(format, everything());
        let path = dir.path().join(format!("twin.{}", format.extension()));
        export(&d, &o, &path);
        let first = std::fs::read(&path).unwrap();
        export(&d, &o, &path);
        assert!(first == std::fs::read(&path).unwrap(), "{format:?} differs");
    }
}

#[test]
fn frame_off_leaves_every_file_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let d = design();
    // Sizes changed but nothing enabled: not one byte may change.
    let off = FrameSpec {
        margin_um: 7.0,
        frame_width_um: 3.0,
        ..FrameSpec::default()
    };
    for format in MaskFormat::ALL {
        // One file name: the notes name the sidecar, so the name is part of the bytes.
        let a = dir.path().join(format!("a.{}", format.extension()));
        export(&d, &options(format, FrameSpec::default()), &a);
        let plain = std::fs::read(&a).unwrap();
        export(&d, &options(format, off.clone()), &a);
        assert!(plain == std::fs::read(&a).unwrap(), "{format:?}");
    }
    // A PNG is a raster of the active area: a frame asked for is not drawn, and says so.
    let png = dir.path().join("a.png");
    let before = std::fs::read(&png).unwrap();
    let r = export(&d, &options(MaskFormat::Png, everything()), &png);
    assert!(before == std::fs::read(&png).unwrap());
    assert!(
        r.lines().iter().any(|l| l.contains("not drawn")),
        "{:?}",
        r.lines()
    );
}

#[test]
fn svg_groups_the_frame_and_widens_its_view_box() {
    let dir = tempfile::tempdir().unwrap();
    let d = design();
    let o = options(MaskFormat::Svg, everything());
    let path = dir.path().join("f.svg");
    export(&d, &o, &path);
    let text = std::fs::read_to_string(&path).unwrap();
    for needle in ["<g id=\"frame\"", "<g id=\"marks\"", "<text id=\"label\""] {
        assert!(text.contains(needle), "no {needle}");
    }
    let r = region_um(&d, &o);
    let view = text.split("viewBox=\"").nth(1).unwrap();
    let x0: f64 = view.split(' ').next().unwrap().parse().unwrap();
    // The marks reach margin + width + margin + size = 210 µm beyond the region.
    assert!((x0 - (r[0] - 210.0)).abs() < 1e-9, "{x0} vs {r:?}");
}

#[test]
fn layer_map_moves_the_frame_and_refuses_a_clash_only_when_drawn() {
    let dir = tempfile::tempdir().unwrap();
    let d = design();
    let mut o = options(MaskFormat::Gds, everything());
    o.layer_map = Some(LayerMap::parse("frame 20/3\nmarks 21/0\nlabel 22/1\n").unwrap());
    let path = dir.path().join("m.gds");
    export(&d, &o, &path);
    let v = python_check(&["gds-layers", s(&path)]);
    assert_eq!(v["layers"]["20/3"]["polygons"], 4, "{v}");
    assert_eq!(v["layers"]["21/0"]["polygons"], 4, "{v}");
    assert!(
        v["texts"]
            .as_array()
            .unwrap()
            .iter()
            .any(|t| t["layer"] == "22/1")
    );
    o.layer_map = Some(LayerMap::parse("frame 1/0\n").unwrap());
    let e = export_mask(&d, &o, &path, &Progress::new()).unwrap_err();
    assert!(e.to_string().contains("frame"), "{e}");
    o.frame.frame = false;
    export(&d, &o, &path);
}

#[test]
fn cli_draws_the_frame_and_refuses_bad_sizes_with_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.gds");
    let base = [
        "export",
        "--format",
        "gds",
        "--region",
        "2x2",
        "--out",
        s(&out),
    ];
    let (ok, stdout, stderr) = run_cli(
        &[
            &base[..],
            &["--frame", "--marks", "--label", "--deterministic"],
        ]
        .concat(),
    );
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("frame on 10/0, marks on 11/0, label on 12/0"),
        "{stdout}"
    );
    let v = python_check(&["gds-layers", s(&out)]);
    assert_eq!(v["layers"]["10/0"]["polygons"], 4);
    std::fs::remove_file(&out).unwrap();
    for (flag, value, needle) in [
        ("--frame-margin-um", "-5", "frame margin"),
        ("--frame-margin-um", "NaN", "frame margin"),
        ("--frame-width-um", "1e308", "frame width"),
        ("--mark-size-um", "0", "mark size"),
        ("--mark-arm-width-um", "150", "mark arm width"),
        ("--label-height-um", "inf", "label height"),
    ] {
        let (ok, stdout, stderr) = run_cli(&[&base[..], &["--frame", flag, value]].concat());
        assert!(!ok, "{flag} {value} must fail");
        assert!(stdout.is_empty(), "{flag} {value}: {stdout}");
        assert!(stderr.contains(needle), "{flag} {value}: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{flag} {value}: {stderr}");
        assert!(!out.exists(), "{flag} {value} wrote the mask");
    }
    let (ok, _, stderr) = run_cli(&[&base[..], &["--frame-margin-um", "wide"]].concat());
    assert!(!ok && stderr.contains("--frame-margin-um"), "{stderr}");
}

#[test]
fn the_dialog_turns_the_frame_on_and_the_export_draws_it() {
    use egui_kittest::kittest::Queryable;
    use udc_studio::app::DisplayAction;
    let dir = tempfile::tempdir().unwrap();
    let mut h = crate::common::studio(dir.path(), false, std::time::Duration::from_secs(3600));
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    h.step();
    h.get_by_label("File").click();
    h.step();
    h.step();
    h.get_by_label("Export mask…").click();
    for _ in 0..4 {
        h.step();
    }
    assert!(
        h.query_by_label("Frame width").is_none(),
        "sizes hidden while off"
    );
    h.get_by_label("Die frame").click();
    h.step();
    h.get_by_label("Label").click();
    h.step();
    h.step();
    let f = h.state().display().mask_export().options().frame.clone();
    assert!(f.frame && f.label && !f.marks, "{f:?}");
    assert!(h.query_by_label("Frame width").is_some());
    assert!(h.query_by_label("Label height").is_some());
    assert!(h.query_by_label("Mark size").is_none());
    let path = dir.path().join("framed.gds");
    h.state_mut()
        .act(DisplayAction::WriteMask(Some(path.clone())));
    crate::common::step_until(&mut h, "the mask export", |app| {
        !app.display().mask_export().is_running()
    });
    let v = python_check(&["gds-layers", s(&path)]);
    assert_eq!(v["layers"]["10/0"]["polygons"], 4, "{v}");
    assert!(v["layers"].get("11/0").is_none());
    assert!(
        v["texts"]
            .as_array()
            .unwrap()
            .iter()
            .any(|t| t["layer"] == "12/0")
    );
}
