//! `udc-studio denoise`: BM3D (grey) or CBM3D (colour) on one image file, written back as the
//! same kind of file, with PSNR against a clean reference when one is given.
//!
//! Everything that can be wrong with the inputs is checked before the denoiser runs (it is the
//! slow part) and before anything is written, so a refused run leaves no file behind.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;
use ndarray::Array2;

use udc_core::Progress;
use udc_core::restore::quality::psnr_db_planes;
use udc_io::IoError;
use udc_io::photo::planes::{ImageKind, ImagePlanes, read_planes, write_planes};
use udc_io::safe_file::{TempFile, check_not_an_input};

/// The smallest side BM3D works on: one 8×8 block.
pub const MIN_SIDE_PX: usize = 8;

/// Arguments of `udc-studio denoise`.
#[derive(Debug, Args)]
pub struct DenoiseArgs {
    /// The noisy image: PNG (8/16-bit), TIFF (8/16-bit or 32-bit float) or OpenEXR, grey or RGB
    /// (alpha is dropped). Integer samples are scaled to [0, 1]; float samples are used as they
    /// are.
    #[arg(long, value_name = "IN")]
    pub image: PathBuf,
    /// The noise variance σ² on the image's [0, 1] scale (σ = 10/255 on an 8-bit image is
    /// σ² ≈ 0.00154).
    #[arg(long, value_name = "S")]
    pub sigma2: f64,
    /// The denoised image, the same kind as the input: .png → 16-bit PNG, .tif/.tiff → 16-bit
    /// TIFF, .exr → float EXR; grey stays grey.
    #[arg(long, value_name = "OUT")]
    pub out: PathBuf,
    /// The clean image (same size and channels): report the PSNR of the input and of the output
    /// against it (peak 1).
    #[arg(long, value_name = "CLEAN")]
    pub reference: Option<PathBuf>,
    /// Print one JSON object to stdout instead of a line.
    #[arg(long)]
    pub json: bool,
}

/// Runs `denoise`.
///
/// # Errors
/// A bad σ², an unreadable, too small or mismatched image, an output of an unknown or different
/// kind or in a folder that cannot take a file, or a failure of the denoiser.
pub fn denoise_cmd(args: &DenoiseArgs) -> Result<()> {
    if !udc_core::denoise::sigma2_in_range(args.sigma2) {
        bail!(
            "--sigma2: the noise variance must be a positive finite number from {:e} to {} \
             (images are in [0, 1]; got {:?})",
            udc_core::denoise::MIN_SIGMA2,
            udc_core::denoise::MAX_SIGMA2,
            args.sigma2
        );
    }
    let out_kind = ImageKind::of_extension(&args.out).context("--out")?;
    let mut inputs = vec![args.image.as_path()];
    inputs.extend(args.reference.as_deref());
    check_not_an_input(&args.out, &inputs)?;
    let noisy = read_planes(&args.image)?;
    check_kind(&noisy, out_kind, &args.out)?;
    check_size(&noisy, &args.image)?;
    let reference = match &args.reference {
        Some(path) => Some(read_reference(path, &noisy)?),
        None => None,
    };
    check_writable(&args.out)?;

    let t0 = Instant::now();
    let denoised = udc_core::denoise::bm3d(&noisy.planes, args.sigma2, &Progress::new())?;
    let elapsed_ms = t0.elapsed().as_secs_f64() * 1e3;
    let (w, h) = noisy.size();
    if denoised.len() != noisy.planes.len() || denoised.iter().any(|p| p.dim() != (h, w)) {
        bail!("the denoiser returned planes of another count or size than it was given");
    }
    let refs: Vec<&Array2<f64>> = denoised.iter().collect();
    write_planes(&args.out, &refs, out_kind)?;

    let (psnr_db, noisy_psnr_db) = match &reference {
        Some(clean) => (
            Some(psnr_against(&as_written(&denoised, out_kind), clean)?),
            Some(psnr_against(&noisy.planes, clean)?),
        ),
        None => (None, None),
    };
    report(args, &noisy, elapsed_ms, psnr_db, noisy_psnr_db)
}

/// The output is written as the input's kind: a different extension is a mistake to name.
fn check_kind(noisy: &ImagePlanes, out_kind: ImageKind, out: &Path) -> Result<(), IoError> {
    if noisy.kind == out_kind {
        return Ok(());
    }
    let ext = out
        .extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_default();
    Err(IoError::Image {
        path: out.to_path_buf(),
        message: format!(
            "--out: the input is {} {} image, so the output is one too: name it .{} (not \
             .{ext})",
            if noisy.kind == ImageKind::Exr {
                "an"
            } else {
                "a"
            },
            noisy.kind.name(),
            noisy.kind.extensions()[0],
        ),
    })
}

fn check_size(noisy: &ImagePlanes, path: &Path) -> Result<(), IoError> {
    let (w, h) = noisy.size();
    if w < MIN_SIDE_PX || h < MIN_SIDE_PX {
        return Err(IoError::Image {
            path: path.to_path_buf(),
            message: format!(
                "the image is {w}×{h} pixels; BM3D needs at least {MIN_SIDE_PX}×{MIN_SIDE_PX}"
            ),
        });
    }
    Ok(())
}

/// The reference's planes, which must match the noisy image's size and channel count.
fn read_reference(path: &Path, noisy: &ImagePlanes) -> Result<Vec<Array2<f64>>, IoError> {
    let clean = read_planes(path)?;
    let channels = |n: usize| if n == 1 { "grey" } else { "RGB" };
    let ((w, h), (rw, rh)) = (noisy.size(), clean.size());
    if (w, h) != (rw, rh) || noisy.planes.len() != clean.planes.len() {
        return Err(IoError::Image {
            path: path.to_path_buf(),
            message: format!(
                "--reference: the reference is {rw}×{rh} {} but the image is {w}×{h} {}; give \
                 the clean version of the same image",
                channels(clean.planes.len()),
                channels(noisy.planes.len())
            ),
        });
    }
    Ok(clean.planes)
}

/// Fails now, not after the denoiser ran, when the output cannot be written: a folder in its
/// place, or a folder that does not exist or cannot take a file (the probe is removed at once).
fn check_writable(out: &Path) -> Result<(), IoError> {
    if out.is_dir() {
        return Err(IoError::NotAFile {
            path: out.to_path_buf(),
            kind: "a directory",
        });
    }
    TempFile::beside(out).map(drop)
}

/// What an integer file holds (clipped to `[0, 1]`), so the PSNR scores the written file.
fn as_written(planes: &[Array2<f64>], kind: ImageKind) -> Vec<Array2<f64>> {
    match kind {
        ImageKind::Exr => planes.to_vec(),
        ImageKind::Png | ImageKind::Tiff => planes
            .iter()
            .map(|p| p.mapv(|v| v.clamp(0.0, 1.0)))
            .collect(),
    }
}

fn psnr_against(test: &[Array2<f64>], clean: &[Array2<f64>]) -> Result<f64> {
    Ok(psnr_db_planes(test, clean, 1.0)?)
}

fn report(
    args: &DenoiseArgs,
    noisy: &ImagePlanes,
    elapsed_ms: f64,
    psnr_db: Option<f64>,
    noisy_psnr_db: Option<f64>,
) -> Result<()> {
    let (w, h) = noisy.size();
    let channels = noisy.planes.len();
    if args.json {
        // An infinite PSNR (identical images) serialises as null, as in `restore`.
        let v = serde_json::json!({
            "sigma2": args.sigma2,
            "elapsed_ms": elapsed_ms,
            "width": w,
            "height": h,
            "channels": channels,
            "psnr_db": psnr_db,
            "noisy_psnr_db": noisy_psnr_db,
            "out": args.out.display().to_string(),
        });
        return super::emit_json(&v);
    }
    let method = if channels == 3 { "CBM3D" } else { "BM3D" };
    let scores = match (psnr_db, noisy_psnr_db) {
        (Some(p), Some(n)) => format!("; PSNR {p:.2} dB (input {n:.2} dB)"),
        _ => String::new(),
    };
    println!(
        "{method} σ² = {:.4e}: {w}×{h}, {channels} channel{} in {elapsed_ms:.0} ms{scores} → {}",
        args.sigma2,
        if channels == 1 { "" } else { "s" },
        args.out.display()
    );
    Ok(())
}
