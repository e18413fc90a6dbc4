use udc_studio::core::*;
use udc_studio::core::design::*;
fn main() {
    let mut d = Design::default_toled();
    let arg = std::env::args().nth(1).unwrap_or_default();
    if arg == "open" { d.opening = Opening::open(21, 168.0); }
    if arg == "rand" { d.tiling.mode = TilingMode::RandomD4; }
    for q in [Quality::Full, Quality::Preview, Quality::Full, Quality::Preview] {
        let t = std::time::Instant::now();
        let a = analyze::analyze_with(&d, &analyze::AnalyzeOptions{quality:q, expected_psf:true}, &Progress::new()).unwrap();
        println!("{q:?} {:.1} ms (wall {:?}) ltr {:.4} of {:.4} linv {:.4}", a.elapsed_ms, t.elapsed(), a.ltr, a.open_fraction, a.invertibility_loss);
        for c in &a.channels { println!("  {} {:?} auc {:.5} mean {:.5} in-window {:.5}", c.name, c.fft_sizes, c.mtf.auc_radial_min, c.mtf.auc_radial_mean, c.energy_in_window); }
        for w in &a.warnings { println!("  W: {w}"); }
    }
}
