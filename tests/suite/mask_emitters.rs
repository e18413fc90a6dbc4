//! The emitter layer in GDSII: R, G, B subpixels on their own layers (21/0, 22/0, 23/0), read
//! back with gdstk (an independent reader) with the area the design gives them.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::process::Command;

use udc_studio::core::Progress;
use udc_studio::core::design::{SubpixelChecks, TilingMode};
use udc_studio::core::mask::{BorderPolicy, MaskRegion, MaskSpec};
use udc_studio::io::design::presets::load_preset;
use udc_studio::io::mask::{ExportOptions, MaskFormat, export_mask};

const AREAS_PY: &str = r#"
import sys, json, gdstk
lib = gdstk.read_gds(sys.argv[1])
top = lib.top_level()[0]
areas = {}
for p in top.get_polygons():
    key = f"{p.layer}/{p.datatype}"
    areas[key] = areas.get(key, 0.0) + p.area()
print(json.dumps(areas))
"#;

#[test]
fn emitters_are_exported_on_their_own_gds_layers() {
    for mode in [TilingMode::Repeat, TilingMode::RandomD4] {
        let mut d = load_preset("toled-150dpi").unwrap();
        d.tiling.mode = mode;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.gds");
        let o = ExportOptions {
            format: MaskFormat::Gds,
            spec: MaskSpec {
                region: MaskRegion::Block { cols: 3, rows: 2 },
                border: BorderPolicy::Cut,
                ..MaskSpec::default()
            },
            deterministic: true,
            ..ExportOptions::default()
        };
        export_mask(&d, &o, &path, &Progress::new()).unwrap();
        let out = Command::new("python3")
            .args(["-c", AREAS_PY, path.to_str().unwrap()])
            .output()
            .expect("python3 with gdstk is required (pip install gdstk)");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let areas: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let checks = SubpixelChecks::of(d.subpixels.as_ref().unwrap(), d.opening.cell_um());
        for (k, layer) in ["21/0", "22/0", "23/0"].into_iter().enumerate() {
            let area_um2 = areas[layer].as_f64().unwrap_or(0.0);
            let want = 6.0 * checks.area_um2[k];
            assert!(
                (area_um2 - want).abs() < 1e-3 * want,
                "{mode:?} layer {layer}: {area_um2} µm² vs {want}"
            );
        }
        assert!(
            areas["1/0"].as_f64().unwrap_or(0.0) > 0.0,
            "the openings stay: {areas}"
        );
    }
}

#[test]
fn emitter_layers_follow_the_layer_map_and_oasis_draws_them_like_gds() {
    use udc_studio::io::fab::LayerMap;
    let dir = tempfile::tempdir().unwrap();
    let mut d = load_preset("l2inv-random").unwrap();
    assert!(d.subpixels.is_some(), "the preset carries a placement");
    d.tiling.mode = TilingMode::RandomD4;
    let map = LayerMap::parse("emitter_green 40/2\n").unwrap();
    let o = |format| ExportOptions {
        format,
        spec: MaskSpec {
            region: MaskRegion::Block { cols: 4, rows: 3 },
            border: BorderPolicy::Cut,
            ..MaskSpec::default()
        },
        layer_map: Some(map.clone()),
        deterministic: true,
        ..ExportOptions::default()
    };
    let (gds, oas) = (dir.path().join("e.gds"), dir.path().join("e.oas"));
    let rg = export_mask(&d, &o(MaskFormat::Gds), &gds, &Progress::new()).unwrap();
    export_mask(&d, &o(MaskFormat::Oas), &oas, &Progress::new()).unwrap();
    // The fab's layer map file names every emitter layer, the mapped one moved.
    let written = std::fs::read_to_string(rg.fab_files.layers.clone().unwrap()).unwrap();
    let back = LayerMap::parse(&written).unwrap();
    assert_eq!(back.get("emitter_red"), Some((21, 0)));
    assert_eq!(back.get("emitter_green"), Some((40, 2)));
    assert_eq!(back.get("emitter_blue"), Some((23, 0)));
    assert!(
        rg.lines().iter().any(|l| l.contains("emitter_green 40/2")),
        "{:?}",
        rg.lines()
    );
    // KLayout: each emitter layer of the OASIS XORs to nothing against the GDSII's.
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mask_check.py");
    for (layer, datatype) in [("21", "0"), ("40", "2"), ("23", "0")] {
        let out = Command::new("python3")
            .args([script, "klayout", oas.to_str().unwrap(), layer, datatype])
            .arg(gds.to_str().unwrap())
            .output()
            .expect("python3 with klayout is required");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let k: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert!(
            k["area_um2"].as_f64().unwrap() > 0.0,
            "{layer}/{datatype}: {k}"
        );
        assert_eq!(
            k["xor_area_um2"].as_f64().unwrap(),
            0.0,
            "{layer}/{datatype}: {k}"
        );
    }
    // A design without emitters writes no emitter layer.
    let mut bare = d.clone();
    bare.subpixels = None;
    let rb = export_mask(
        &bare,
        &o(MaskFormat::Gds),
        &dir.path().join("b.gds"),
        &Progress::new(),
    )
    .unwrap();
    let none = std::fs::read_to_string(rb.fab_files.layers.clone().unwrap()).unwrap();
    assert!(!none.contains("emitter"), "{none}");
}
