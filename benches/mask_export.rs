//! Streaming a whole display to OASIS, then to GDSII: the 600 DPI T-OLED pixel, random D4
//! tiling, 1080 × 2400 pixels (2.6 M placements). Prints the wall time, the file size and the
//! process's peak resident memory (`VmHWM` from /proc/self/status; the process does nothing
//! else, and OASIS, the smaller, runs first, so each peak is its export's). The target: ≤ 10 s
//! and ≤ 500 MB.
//!
//! Run with `cargo bench --bench mask_export`.

use std::time::Instant;

use udc_studio::core::Progress;
use udc_studio::core::design::TilingMode;
use udc_studio::core::mask::{MaskRegion, MaskSpec};
use udc_studio::io::design::presets::load_preset;
use udc_studio::io::mask::{ExportOptions, MaskFormat, export_mask};

/// `VmHWM` in MB (10⁶ bytes), or `None` without /proc.
fn vm_hwm_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0 / 1e6)
}

fn show(mb: Option<f64>) -> String {
    mb.map_or_else(|| "unavailable".to_string(), |v| format!("{v:.1} MB"))
}

fn main() {
    // `cargo test --benches` runs benches with `--bench` absent; only measure when benching.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    let mut design = match load_preset("toled-600dpi") {
        Ok(d) => d,
        Err(e) => {
            eprintln!("cannot load the preset: {e}");
            std::process::exit(1);
        }
    };
    design.tiling.mode = TilingMode::RandomD4;
    design.tiling.seed = 1;
    let dir = std::env::temp_dir().join(format!("udc-mask-bench-{}", std::process::id()));
    if let Err(e) = std::fs::create_dir_all(&dir) {
        eprintln!("cannot create {}: {e}", dir.display());
        std::process::exit(1);
    }
    for format in [MaskFormat::Oas, MaskFormat::Gds] {
        measure(&design, format, &dir);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn measure(design: &udc_studio::core::design::Design, format: MaskFormat, dir: &std::path::Path) {
    let options = ExportOptions {
        format,
        spec: MaskSpec {
            region: MaskRegion::Block {
                cols: 1080,
                rows: 2400,
            },
            ..MaskSpec::default()
        },
        ..ExportOptions::default()
    };
    let path = dir.join(format!("display.{}", format.extension()));
    let baseline = vm_hwm_mb();
    let start = Instant::now();
    let result = export_mask(design, &options, &path, &Progress::new());
    let seconds = start.elapsed().as_secs_f64();
    let peak = vm_hwm_mb();
    let _ = std::fs::remove_file(&path);
    match result {
        Ok(report) => {
            println!(
                "mask_export/{} 600 DPI 1080x2400 random-d4: {seconds:.2} s, {} references + {} \
                 repeated, {:.1} MB file, peak RSS {} (baseline {})",
                format.extension(),
                report.counts.references,
                report.counts.arrays,
                report.counts.bytes as f64 / 1e6,
                show(peak),
                show(baseline)
            );
        }
        Err(e) => {
            eprintln!("export failed: {e}");
            std::process::exit(1);
        }
    }
}
