//! The thesis's published numbers and trends (conventions.md §4, thesis §3.4.1 and Fig. 3.7).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use udc_core::Progress;
use udc_core::analysis::analyze::analyze;
use udc_core::design::{Design, Opening, TilingMode};

fn toled() -> Design {
    Design::default_toled()
}

#[test]
fn open_aperture_auc_reproduces_the_thesis() {
    let mut d = toled();
    d.opening = Opening::open(21, 168.0);
    let a = analyze(&d, &Progress::new()).expect("analysis");
    let want = [("R", 0.3068), ("G", 0.3170), ("B", 0.3274)];
    for (ch, (name, auc)) in a.channels.iter().zip(want) {
        assert_eq!(ch.name, name);
        let rel = (ch.mtf.auc_radial_min - auc).abs() / auc;
        assert!(
            rel < 0.003,
            "{name}: AUC {} vs thesis {auc} ({:.2} %)",
            ch.mtf.auc_radial_min,
            100.0 * rel
        );
    }
    assert_eq!(
        a.channels
            .iter()
            .map(|c| c.fft_sizes[0])
            .collect::<Vec<_>>(),
        vec![1524, 1324, 1174]
    );
    assert!((a.ltr - 1.0).abs() < 1e-12);
}

#[test]
fn toled_repeat_collapses_and_random_tiling_lifts_the_auc() {
    let repeat = analyze(&toled(), &Progress::new()).expect("analysis");
    let mut d = toled();
    d.tiling.mode = TilingMode::RandomD4;
    let random = analyze(&d, &Progress::new()).expect("analysis");
    for (rep, rnd) in repeat.channels.iter().zip(&random.channels) {
        // The periodic slit's radial minimum falls to ≈0 within a few rings (Fig. 3.7).
        let first_null = rep
            .mtf
            .radial_min
            .iter()
            .position(|v| *v < 0.01)
            .expect("a null");
        assert!(
            first_null <= 8,
            "{}: first near-null at ring {first_null}",
            rep.name
        );
        assert!(
            rnd.mtf.auc_radial_min > 3.0 * rep.mtf.auc_radial_min,
            "{}: random {} vs repeat {}",
            rep.name,
            rnd.mtf.auc_radial_min,
            rep.mtf.auc_radial_min
        );
        // Random tiling lifts the nulls: far fewer rings whose minimum is ≈0.
        let nulls = |v: &[f64]| v.iter().filter(|x| **x < 1e-3).count();
        let (n_rep, n_rnd) = (nulls(&rep.mtf.radial_min), nulls(&rnd.mtf.radial_min));
        assert!(
            n_rnd * 4 < n_rep,
            "{}: {n_rnd} null rings random vs {n_rep} repeat",
            rep.name
        );
    }
    // Random tiling does not change how much light passes.
    assert!((repeat.ltr - random.ltr).abs() < 0.005);
    assert!((repeat.open_fraction - 5.0 / 21.0).abs() < 1e-12);
    // …and the invertibility loss improves.
    assert!(random.invertibility_loss < repeat.invertibility_loss - 0.05);
}
