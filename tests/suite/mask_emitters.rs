//! The emitter layer in GDSII: R, G, B subpixels on their own layers (21/0, 22/0, 23/0), read
//! back with gdstk (an independent reader) with the area the design gives them.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::process::Command;

use udc_studio::core::Progress;
use udc_studio::core::design::{SubpixelChecks, TilingMode};
use udc_studio::core::mask::{MaskRegion, MaskSpec};
use udc_studio::io::mask::{ExportOptions, MaskFormat, export_mask};
use udc_studio::io::presets::load_preset;

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
