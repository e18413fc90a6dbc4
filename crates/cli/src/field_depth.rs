//! `udc-studio field` and `udc-studio depth`: how the display blur changes over the field and
//! with object distance (thesis §3.7, Figs. 3.29 and 3.31), with the JSON contract scripts use.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use clap::{Args, ValueEnum};
use ndarray::Array2;

use super::DesignSelection;
use udc_core::Progress;
use udc_core::analysis::analyze::Quality;
use udc_core::camera::depth::{DepthSettings, depth_psfs};
use udc_core::camera::field::{FieldSettings, field_psfs};
use udc_io::display::export::write_log_psf_png;
use udc_jobs::backend::BackendFlag;

/// Arguments of `udc-studio field`.
#[derive(Debug, Args)]
pub struct FieldArgs {
    /// The display design.
    #[command(flatten)]
    pub selection: DesignSelection,
    /// Distance from the display to the lens pupil, in mm.
    #[arg(long)]
    pub display_distance_mm: f64,
    /// Points per side of the field grid (3: corners, edges and centre).
    #[arg(long, default_value_t = 3)]
    pub grid: usize,
    /// Field angle of the outer grid points on each axis, in degrees.
    #[arg(long, default_value_t = 30.0)]
    pub max_field_deg: f64,
    /// Noise-to-signal ratio of the Wiener filter behind `residual_rel`.
    #[arg(long, default_value_t = udc_core::restore::THESIS_NSR)]
    pub nsr: f64,
    /// Full-quality sampling (default: the studio's preview sampling, which doubles the fine
    /// PSF spacing only where the AUC stays within 3 %).
    #[arg(long)]
    pub full: bool,
    /// Print one JSON object to stdout instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Write log-scaled PNGs of every PSF and its deblurred residual into this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Also capture this photo patch-wise through the field-dependent PSFs (its corners at the
    /// corner field angles) and through the centre PSF, and restore both with the centre PSF.
    #[arg(long)]
    pub image: Option<PathBuf>,
    /// Light level of the `--image` capture, as the SNR of a white pixel in dB.
    #[arg(long, default_value_t = 28.0, requires = "image")]
    pub snr_db: f64,
    /// Scale the `--image` photo down so its longer side has at most this many pixels.
    #[arg(long, default_value_t = 256, requires = "image")]
    pub max_side_px: u32,
    /// Where the PSFs are computed.
    #[command(flatten)]
    pub backend: BackendFlag,
}

/// Where the camera of `udc-studio depth` focuses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Focus {
    /// On the object (sensor at z2 from the lens law).
    Object,
    /// At infinity (sensor at f): the object is defocused.
    Infinity,
}

/// Arguments of `udc-studio depth`.
#[derive(Debug, Args)]
pub struct DepthArgs {
    /// The display design.
    #[command(flatten)]
    pub selection: DesignSelection,
    /// Object distance z1 from the lens, in mm.
    #[arg(long)]
    pub object_distance_mm: f64,
    /// Lens focal length in mm (default: the design's; the f-number is kept).
    #[arg(long)]
    pub focal_mm: Option<f64>,
    /// Which PSF `residual_rel` reports (both are always in the JSON).
    #[arg(long, value_enum, default_value = "object")]
    pub focus: Focus,
    /// Noise-to-signal ratio of the Wiener filter behind `residual_rel`.
    #[arg(long, default_value_t = udc_core::restore::THESIS_NSR)]
    pub nsr: f64,
    /// Full-quality sampling (default: the studio's preview sampling, which doubles the fine
    /// PSF spacing only where the AUC stays within 3 %).
    #[arg(long)]
    pub full: bool,
    /// Print one JSON object to stdout instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Write log-scaled PNGs of the three PSFs and the two residuals into this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Where the three PSFs are computed (the defocused one, a complex pupil, over the whole
    /// grid).
    #[command(flatten)]
    pub backend: BackendFlag,
}

fn quality(full: bool) -> Quality {
    if full {
        Quality::Full
    } else {
        Quality::Preview
    }
}

/// The channel mean of per-channel planes (for one grey picture).
fn channel_mean(planes: &[Array2<f64>]) -> Option<Array2<f64>> {
    let first = planes.first()?;
    let mut acc = Array2::<f64>::zeros(first.dim());
    for p in planes {
        acc += p;
    }
    acc /= planes.len() as f64;
    Some(acc)
}

fn write_mean(
    dir: &Path,
    name: &str,
    planes: &[Array2<f64>],
    written: &mut Vec<String>,
) -> Result<()> {
    if let Some(m) = channel_mean(planes) {
        let path = dir.join(name);
        write_log_psf_png(&path, &m)?;
        written.push(path.display().to_string());
    }
    Ok(())
}

/// Runs `udc-studio field`.
///
/// # Errors
/// Bad arguments, designs or sampling; unwritable output.
pub fn field_cmd(args: &FieldArgs) -> Result<()> {
    let design = args.selection.resolve()?;
    let settings = FieldSettings {
        display_distance_mm: args.display_distance_mm,
        max_field_deg: args.max_field_deg,
        grid: args.grid,
        nsr: args.nsr,
        quality: quality(args.full),
    };
    let photo = match &args.image {
        Some(path) => {
            if args.max_side_px == 0 {
                bail!("--max-side-px: must be at least 1");
            }
            Some(udc_io::photo::load_photo(path, Some(args.max_side_px))?)
        }
        None => None,
    };
    let route = args.backend.route()?;
    let r = field_psfs(&design, &settings, &route, &Progress::new())?;
    let capture = match &photo {
        Some(planes) => {
            let cap = udc_core::restore::CaptureSettings {
                light: udc_core::restore::Light::SnrDb(args.snr_db),
                ..udc_core::restore::CaptureSettings::default()
            };
            cap.validate()?;
            Some(udc_core::camera::field_capture::field_capture(
                planes,
                &r,
                &cap,
                settings.nsr,
            )?)
        }
        None => None,
    };
    let mut written = Vec::new();
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir)?;
        if let Some(c) = &capture {
            for (name, planes) in [
                ("restored_field.png", &c.restored_field),
                ("restored_invariant.png", &c.restored_invariant),
            ] {
                let path = dir.join(name);
                let refs: Vec<_> = planes.iter().collect();
                udc_io::photo::write_photo_png(&path, &refs)?;
                written.push(path.display().to_string());
            }
        }
        write_mean(dir, "psf_centre.png", &r.centre, &mut written)?;
        for (i, p) in r.points.iter().enumerate() {
            let (row, col) = (i / settings.grid, i % settings.grid);
            write_mean(
                dir,
                &format!("psf_r{row}_c{col}.png"),
                &p.psfs,
                &mut written,
            )?;
            write_mean(
                dir,
                &format!("residual_r{row}_c{col}.png"),
                &p.deblurred,
                &mut written,
            )?;
        }
    }
    if args.json {
        let points: Vec<serde_json::Value> = r
            .points
            .iter()
            .map(|p| {
                serde_json::json!({
                    "field_deg": p.field_deg,
                    "residual_rel": p.residual_rel,
                    "residual_rel_per_channel": p.residual_rel_per_channel,
                    "shift_um": p.shift_um,
                    "image_height_mm": p.image_height_mm,
                    "relative_illumination": p.relative_illumination,
                })
            })
            .collect();
        let mut out = serde_json::json!({
            "design": design.name,
            "tiling": design.tiling.mode.as_str(),
            "display_distance_mm": settings.display_distance_mm,
            "max_field_deg": settings.max_field_deg,
            "grid": settings.grid,
            "nsr": settings.nsr,
            "channels": r.channels,
            "points": points,
            "max_residual_rel": r.max_residual_rel,
            "capture": capture.as_ref().map(|c| serde_json::json!({
                "snr_db": args.snr_db,
                "psnr_db_field": c.psnr_db_field,
                "psnr_db_invariant": c.psnr_db_invariant,
                "ssim_field": c.ssim_field,
                "ssim_invariant": c.ssim_invariant,
            })),
            "outputs": written,
        });
        args.backend.note(&route, &mut out);
        crate::emit_json(&out)?;
        return Ok(());
    }
    println!(
        "{}: tiling {}, display {} mm in front of the pupil; residual after deblurring with the \
         centre PSF (Wiener, nsr {})",
        design.name,
        design.tiling.mode.as_str(),
        settings.display_distance_mm,
        settings.nsr
    );
    println!("field (deg)        shift (µm)          residual_rel  cos4");
    for p in &r.points {
        println!(
            "{:>6.1} {:>6.1}    {:>8.1} {:>8.1}   {:>11.3e}   {:.3}",
            p.field_deg[0],
            p.field_deg[1],
            p.shift_um[0],
            p.shift_um[1],
            p.residual_rel,
            p.relative_illumination
        );
    }
    println!("max residual_rel {:.3e}", r.max_residual_rel);
    if let Some(c) = &capture {
        println!(
            "photo restored with the centre PSF: field-dependent capture {:.2} dB / SSIM {:.4}, \
             centre PSF everywhere {:.2} dB / SSIM {:.4}",
            c.psnr_db_field, c.ssim_field, c.psnr_db_invariant, c.ssim_invariant
        );
    }
    for w in &written {
        println!("wrote {w}");
    }
    if let Some(line) = args.backend.line(&route) {
        println!("{line}");
    }
    Ok(())
}

/// Runs `udc-studio depth`.
///
/// # Errors
/// Bad arguments, designs or sampling; unwritable output.
pub fn depth_cmd(args: &DepthArgs) -> Result<()> {
    let mut design = args.selection.resolve()?;
    if let Some(f) = args.focal_mm {
        if !(f.is_finite() && f > 0.0) {
            bail!("--focal-mm: must be a positive number of mm (got {f})");
        }
        design.optics.focal_length_mm = f;
        design.optics.recipe = udc_core::design::OpticsRecipe::Custom;
        design
            .validate()
            .map_err(|e| anyhow::anyhow!("--focal-mm: {e}"))?;
    }
    let settings = DepthSettings {
        object_distance_mm: args.object_distance_mm,
        nsr: args.nsr,
        quality: quality(args.full),
    };
    let route = args.backend.route()?;
    let r = depth_psfs(&design, &settings, &route, &Progress::new())?;
    let mut written = Vec::new();
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir)?;
        write_mean(dir, "psf_infinity.png", &r.infinity, &mut written)?;
        write_mean(dir, "psf_focused.png", &r.focused, &mut written)?;
        write_mean(dir, "psf_defocused.png", &r.defocused, &mut written)?;
        write_mean(
            dir,
            "residual_focused.png",
            &r.deblurred_focused,
            &mut written,
        )?;
        write_mean(
            dir,
            "residual_defocused.png",
            &r.deblurred_defocused,
            &mut written,
        )?;
    }
    let residual = match args.focus {
        Focus::Object => r.residual_rel_focused,
        Focus::Infinity => r.residual_rel_defocused,
    };
    if args.json {
        let mut out = serde_json::json!({
            "design": design.name,
            "object_distance_mm": r.object_distance_mm,
            "focal_mm": r.focal_length_mm,
            "image_distance_mm": r.image_distance_mm,
            "psf_scale": r.psf_scale,
            "focus": match args.focus { Focus::Object => "object", Focus::Infinity => "infinity" },
            "residual_rel": residual,
            "residual_rel_focused_at_object": r.residual_rel_focused,
            "residual_rel_focused_at_infinity": r.residual_rel_defocused,
            "residual_rel_per_channel": {
                "object": r.residual_rel_focused_per_channel,
                "infinity": r.residual_rel_defocused_per_channel,
            },
            "defocus_waves": r.defocus_waves,
            "defocus_blur_um": r.defocus_blur_um,
            "defocused_energy_in_window": r.defocused_energy_in_window,
            "nsr": settings.nsr,
            "channels": r.channels,
            "outputs": written,
        });
        args.backend.note(&route, &mut out);
        crate::emit_json(&out)?;
        return Ok(());
    }
    println!(
        "{}: object at z1 = {} mm, f = {} mm -> z2 = {:.4} mm (lens law), PSF scale z2/f = {:.4} \
         ({:+.2} %)",
        design.name,
        r.object_distance_mm,
        r.focal_length_mm,
        r.image_distance_mm,
        r.psf_scale,
        100.0 * (r.psf_scale - 1.0)
    );
    println!(
        "residual_rel after deblurring with the infinity PSF: focused at the object {:.3e}, \
         focused at infinity {:.3e}",
        r.residual_rel_focused, r.residual_rel_defocused
    );
    let waves: Vec<String> = r.defocus_waves.iter().map(|w| format!("{w:.2}")).collect();
    println!(
        "focused at infinity: defocus at the pupil rim {} waves ({}), geometric blur {:.1} µm",
        waves.join(" / "),
        r.channels.join(" / "),
        r.defocus_blur_um
    );
    for w in &written {
        println!("wrote {w}");
    }
    if let Some(line) = args.backend.line(&route) {
        println!("{line}");
    }
    Ok(())
}
