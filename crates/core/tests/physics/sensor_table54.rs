//! Table 5.4's ordering on every scene the repository ships, in luminance and in colour:
//! varying gain and binning together is best or tied on the worst ROI, and beats the
//! conventional sensor.

use std::path::Path;

use udc_core::Progress;
use udc_core::sensor::{Cfa, SensorSettings, run};
use udc_io::photo::hdr::load_hdr;

#[test]
fn vary_gain_and_bin_is_best_or_tied_on_every_shipped_scene() {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("assets/hdr");
    let mut scenes: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "exr"))
        .collect();
    scenes.sort();
    assert!(scenes.len() >= 3, "{scenes:?}");
    for path in &scenes {
        let scene = load_hdr(path).unwrap();
        for cfa in [Cfa::None, Cfa::Rggb] {
            let settings = SensorSettings {
                cfa,
                ..SensorSettings::default()
            };
            let r = run(&scene, &settings, &Progress::new()).unwrap();
            let names: Vec<&str> = r.strategies.iter().map(|s| s.name.as_str()).collect();
            assert_eq!(names[3], "vary-gain/vary-bin");
            let worst: Vec<f64> = r.strategies.iter().map(|s| s.worst_roi_ssim).collect();
            let what = format!("{} {cfa:?}: {worst:?}", path.display());
            // Best or tied (seeds move the worst ROI by about ±0.005)...
            assert!(worst.iter().all(|w| *w <= worst[3] + 0.005), "{what}");
            // ...and clearly better than the conventional sensor.
            assert!(worst[3] > worst[0] + 0.02, "{what}");
        }
    }
}
