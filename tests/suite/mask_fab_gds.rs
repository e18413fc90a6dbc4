//! What a mask house checks before accepting a file: GDSII record limits, byte-identical
//! deterministic exports, cell names that merge without a clash, the phase plate's notes off
//! its level layers, the checksum, the manifest and the layer map beside every export.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::collections::BTreeSet;
use std::path::Path;

use gds21::{GdsElement, GdsLibrary};
use udc_studio::core::Progress;
use udc_studio::core::design::{Design, Opening, TilingMode};
use udc_studio::core::mask::{BorderPolicy, MaskRegion, MaskSpec};
use udc_studio::core::phase::PhaseDesign;
use udc_studio::io::error::LayerMapError;
use udc_studio::io::fab::{LayerMap, MAX_XY_POINTS, outline_paths, sha256_hex};
use udc_studio::io::mask::{ExportOptions, MaskFormat, MaskReport, export_mask};
use udc_studio::io::phase::export::{GDS_NOTE_LAYER, HeightFormat, HeightParams, write_height};

/// A 16×16-cell opening, 64 µm pitch, `name` and `seed` making designs differ.
fn design(name: &str, seed: u64) -> Design {
    let mut d = Design::default_toled();
    d.name = name.into();
    let cells: Vec<Vec<f64>> = (0..16)
        .map(|i| {
            (0..16)
                .map(|j| f64::from(u8::from((i * 7 + j * 3 + seed as usize) % 5 < 2)))
                .collect()
        })
        .collect();
    d.opening = Opening {
        pitch_um: 64.0,
        cells,
        polygons: Vec::new(),
    };
    d.tiling.mode = TilingMode::RandomD4;
    d.tiling.seed = seed;
    d
}

fn options(format: MaskFormat, region: MaskRegion) -> ExportOptions {
    ExportOptions {
        format,
        spec: MaskSpec {
            region,
            border: BorderPolicy::Cut,
            ..MaskSpec::default()
        },
        deterministic: true,
        ..ExportOptions::default()
    }
}

fn export(d: &Design, o: &ExportOptions, path: &Path) -> MaskReport {
    export_mask(d, o, path, &Progress::new()).unwrap()
}

/// Every XY record of a GDSII stream: (points, record bytes), read from the raw records.
fn xy_records(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut k = 0;
    while k + 4 <= bytes.len() {
        let len = usize::from(u16::from_be_bytes([bytes[k], bytes[k + 1]]));
        assert!(len >= 4, "record at {k} of length {len}");
        if bytes[k + 2] == 0x10 {
            out.push(((len - 4) / 8, len));
        }
        k += len;
    }
    assert_eq!(k, bytes.len());
    out
}

fn assert_within_limits(bytes: &[u8]) {
    for (points, len) in xy_records(bytes) {
        assert!(points <= 8191, "{points} points");
        assert!(len <= 32767, "an XY record of {len} bytes");
    }
}

#[test]
fn fab_deterministic_gds_exports_are_byte_identical() {
    let dir = tempfile::tempdir().unwrap();
    let d = design("twin", 3);
    let o = options(MaskFormat::Gds, MaskRegion::Block { cols: 4, rows: 3 });
    // The same path twice: the notes name the sidecar, so the file name is part of the bytes.
    let a = dir.path().join("a.gds");
    let first = export(&d, &o, &a);
    let bytes = std::fs::read(&a).unwrap();
    let sum = std::fs::read(&first.fab_files.checksum).unwrap();
    export(&d, &o, &a);
    assert!(
        bytes == std::fs::read(&a).unwrap(),
        "the two exports differ"
    );
    assert!(sum == std::fs::read(&first.fab_files.checksum).unwrap());
}

#[test]
fn fab_two_designs_merge_without_a_cell_name_clash() {
    let dir = tempfile::tempdir().unwrap();
    let o = options(MaskFormat::Gds, MaskRegion::Block { cols: 2, rows: 2 });
    let names = |d: &Design, file: &str| -> BTreeSet<String> {
        let path = dir.path().join(file);
        let r = export(d, &o, &path);
        let top = r.options.top_cell.clone().unwrap();
        assert!(top.len() <= 24 && (top.starts_with("MASK_A_") || top.starts_with("MASK_B_")));
        let lib = GdsLibrary::open(&path).unwrap();
        lib.structs.iter().map(|s| s.name.clone()).collect()
    };
    let a = names(&design("mask a", 1), "a.gds");
    let b = names(&design("mask b", 2), "b.gds");
    assert!(a.len() >= 2 && b.len() >= 2);
    assert!(a.is_disjoint(&b), "{a:?} vs {b:?}");
    for n in a.iter().chain(&b) {
        assert!(n.len() <= 32 && n.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'));
    }
}

/// A 512×512-cell opening in one comb-shaped polygon of ~170 000 vertices: it must reach the
/// file split into boundaries within the record limits, with the same total area.
#[test]
fn fab_huge_polygons_are_split_within_the_record_limits() {
    let n = 512;
    let cells: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| {
                    let open = j == 0 || i % 3 == 0 || (i % 3 == 1 && j % 2 == 0);
                    f64::from(u8::from(open))
                })
                .collect()
        })
        .collect();
    let open_cells: f64 = cells.iter().flatten().sum();
    let mut d = design("comb", 1);
    d.opening = Opening {
        pitch_um: n as f64,
        cells,
        polygons: Vec::new(),
    };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("comb.gds");
    export(&d, &options(MaskFormat::Gds, MaskRegion::PIXEL), &path);
    let bytes = std::fs::read(&path).unwrap();
    assert_within_limits(&bytes);
    let lib = GdsLibrary::from_bytes(&bytes).unwrap();
    let mut area_nm2 = 0.0;
    let mut boundaries = 0;
    for e in lib.structs.iter().flat_map(|s| &s.elems) {
        if let GdsElement::GdsBoundary(b) = e {
            boundaries += 1;
            let p = &b.xy;
            area_nm2 += p
                .windows(2)
                .map(|w| {
                    f64::from(w[0].x) * f64::from(w[1].y) - f64::from(w[1].x) * f64::from(w[0].y)
                })
                .sum::<f64>()
                / 2.0;
        }
    }
    assert!(boundaries > 1, "the comb was not split");
    // 1 µm cells = 1e6 nm² each; holes (negative area) do not occur in a comb.
    let expect = open_cells * 1e6;
    assert!(
        (area_nm2.abs() - expect).abs() / expect < 1e-9,
        "{area_nm2} vs {expect}"
    );
}

#[test]
fn fab_large_pupil_outline_is_paths_within_the_limits() {
    let mut d = design("big pupil", 5);
    d.tiling.mode = TilingMode::Repeat;
    // f = 40 mm at F/1.6: a 25 mm pupil, ~120 000 pixels of 64 µm.
    d.optics.focal_length_mm = 40.0;
    d.optics.f_number = 1.6;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("pupil.gds");
    let mut o = options(MaskFormat::Gds, MaskRegion::Pupil);
    o.note_layer = 7;
    export(&d, &o, &path);
    let bytes = std::fs::read(&path).unwrap();
    assert_within_limits(&bytes);
    let lib = GdsLibrary::from_bytes(&bytes).unwrap();
    let elems: Vec<&GdsElement> = lib.structs.iter().flat_map(|s| &s.elems).collect();
    let paths = elems
        .iter()
        .filter(|e| matches!(e, GdsElement::GdsPath(p) if p.layer == 7 && p.width == Some(1000)))
        .count();
    assert!(paths >= 1);
    assert!(
        !elems
            .iter()
            .any(|e| matches!(e, GdsElement::GdsBoundary(b) if b.layer == 7)),
        "the outline is not a filled disc"
    );
}

#[test]
fn fab_outline_paths_split_and_chain() {
    let ring: Vec<gds21::GdsPoint> = (0..10_000).map(|i| gds21::GdsPoint::new(i, 0)).collect();
    let paths = outline_paths(&ring, 2, 0, 1000);
    assert_eq!(paths.len(), 3);
    for w in paths.windows(2) {
        assert_eq!(w[0].xy.last(), w[1].xy.first());
    }
    assert!(paths.iter().all(|p| p.xy.len() <= MAX_XY_POINTS));
    let total: usize = paths.iter().map(|p| p.xy.len()).sum();
    // 10 000 points, the closing point, and one shared point per join.
    assert_eq!(total, 10_001 + paths.len() - 1);
    assert_eq!(paths[2].xy.last(), ring.first());
}

#[test]
fn fab_checksum_manifest_and_layer_map_are_written_beside_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let d = design("sidecars", 2);
    for format in MaskFormat::ALL {
        let path = dir.path().join(format!("m.{}", format.extension()));
        let r = export(
            &d,
            &options(format, MaskRegion::Block { cols: 2, rows: 2 }),
            &path,
        );
        let bytes = std::fs::read(&path).unwrap();
        let sum = std::fs::read_to_string(&r.fab_files.checksum).unwrap();
        assert_eq!(
            sum,
            format!("{}  m.{}\n", sha256_hex(&bytes), format.extension())
        );
        let m: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&r.fab_files.manifest).unwrap()).unwrap();
        assert_eq!(m["format"], format.as_str());
        assert_eq!(m["design"]["name"], "sidecars");
        assert_eq!(m["sha256"], sha256_hex(&bytes));
        assert_eq!(m["tool_version"], udc_studio::io::TOOL_VERSION);
        assert_eq!(m["layer_map"][0]["name"], "openings");
        if matches!(format, MaskFormat::Gds | MaskFormat::Oas) {
            let layers = r.fab_files.layers.clone().unwrap();
            let ext = format.extension();
            assert_eq!(m["layer_map_file"], format!("m.{ext}.layers.txt"));
            let map = LayerMap::parse(&std::fs::read_to_string(layers).unwrap()).unwrap();
            assert_eq!(map.get("openings"), Some((1, 0)));
            assert_eq!(map.get("notes"), Some((2, 0)));
        } else {
            assert!(r.fab_files.layers.is_none());
        }
    }
}

#[test]
fn fab_layer_map_moves_every_role() {
    let map =
        LayerMap::parse("# fab layers\nopenings 10/3\noutline 11/0 # path\nnotes 63/5\n").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mapped.gds");
    let mut o = options(MaskFormat::Gds, MaskRegion::Pupil);
    o.layer_map = Some(map);
    export(&design("mapped", 4), &o, &path);
    let lib = GdsLibrary::open(&path).unwrap();
    let mut seen = BTreeSet::new();
    for e in lib.structs.iter().flat_map(|s| &s.elems) {
        match e {
            GdsElement::GdsBoundary(b) => seen.insert(("boundary", b.layer, b.datatype)),
            GdsElement::GdsPath(p) => seen.insert(("path", p.layer, p.datatype)),
            GdsElement::GdsTextElem(t) => seen.insert(("text", t.layer, t.texttype)),
            _ => false,
        };
    }
    let want: BTreeSet<_> = [("boundary", 10, 3), ("path", 11, 0), ("text", 63, 5)].into();
    assert_eq!(seen, want);
    let text = std::fs::read_to_string(dir.path().join("mapped.gds.layers.txt")).unwrap();
    assert!(text.contains("openings 10/3") && text.contains("outline 11/0"));
    let bad = LayerMap::parse("# map\nopenings 1\n").unwrap_err();
    assert_eq!(
        bad,
        LayerMapError::Line {
            line: 2,
            text: "openings 1".into()
        }
    );
    assert!(bad.to_string().contains("line 2"), "{bad}");
    o.layer_map = Some(LayerMap::parse("vias 5/0\n").unwrap());
    let e = export_mask(&design("x", 1), &o, &path, &Progress::new()).unwrap_err();
    assert!(e.to_string().contains("vias"), "{e}");
}

#[test]
fn fab_klayout_lyp_layer_maps_parse() {
    let lyp = r#"<?xml version="1.0" encoding="utf-8"?>
<layer-properties>
 <properties><name>openings (clear)</name><source>4/1@1</source></properties>
 <properties><name>notes</name><source>9/0@1</source></properties>
</layer-properties>"#;
    let map = LayerMap::parse(lyp).unwrap();
    assert_eq!(map.get("openings"), Some((4, 1)));
    assert_eq!(map.get("notes"), Some((9, 0)));
}

#[test]
fn fab_phase_plate_notes_are_off_every_level_layer() {
    let mut d = PhaseDesign::thesis(168.0, 1.0);
    d.height_step_um = Some(0.2);
    let dir = tempfile::tempdir().unwrap();
    let params = HeightParams {
        sample_um: 0.1,
        rows: 4,
        length_um: 100.0,
        base_um: 5.0,
        deterministic: true,
        phase_min_feature_um: 0.0,
    };
    let (a, b) = (dir.path().join("a.gds"), dir.path().join("b.gds"));
    write_height(HeightFormat::Gds, &d, &a, &params).unwrap();
    write_height(HeightFormat::Gds, &d, &b, &params).unwrap();
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    let lib = GdsLibrary::open(&a).unwrap();
    let mut levels = BTreeSet::new();
    let mut notes = BTreeSet::new();
    for e in lib.structs.iter().flat_map(|s| &s.elems) {
        match e {
            GdsElement::GdsBoundary(b) => {
                levels.insert(b.layer);
            }
            GdsElement::GdsTextElem(t) => {
                notes.insert(t.layer);
            }
            _ => {}
        }
    }
    assert_eq!(notes, [GDS_NOTE_LAYER].into());
    assert!(!levels.contains(&GDS_NOTE_LAYER) && !levels.contains(&0));
    assert!(lib.structs[0].name.starts_with("UDC_PHASE_"));
    let map =
        LayerMap::parse(&std::fs::read_to_string(dir.path().join("a.gds.layers.txt")).unwrap())
            .unwrap();
    assert_eq!(map.get("notes"), Some((GDS_NOTE_LAYER, 0)));
    assert_eq!(map.get("level_1"), Some((1, 0)));
    let sum = std::fs::read_to_string(dir.path().join("a.gds.sha256")).unwrap();
    assert!(sum.starts_with(&sha256_hex(&std::fs::read(&a).unwrap())));
}
