//! `restore --psf`: a real capture restored with a measured PSF set, scored against a truth
//! when one is given.

use std::path::Path;

use anyhow::{Context, Result, bail};
use ndarray::Array2;
use serde_json::json;

use udc_core::Progress;
use udc_core::restore::{Method, Padding, quality, restore_capture};
use udc_io::measured::read::{Encoding, FramePick, read_frame};
use udc_io::measured::{SetDefaults, read_psf_set};

use crate::Report;
use crate::denoise::{DenoiseFlags, DenoiseMethod, Sigma2Arg};

/// What `restore --psf` was asked (the restore job's flags that apply to a real capture).
pub struct MeasuredRun<'a> {
    /// The capture.
    pub image: &'a Path,
    /// The PSF set.
    pub psf: &'a Path,
    /// The clean scene to score against.
    pub truth: Option<&'a Path>,
    /// The deblurring, and its name for the JSON (`wiener`, `cg`).
    pub method: (Method, &'static str),
    /// Its FFT padding.
    pub padding: Padding,
    /// The denoising flags.
    pub denoise: &'a DenoiseFlags,
    /// Where to write the images.
    pub out: Option<&'a Path>,
    /// Also write the pictures as figures (`restore --figures`).
    pub figures: bool,
}

/// The note on a PSF set's negative samples set to 0 (`share`: the largest share of a
/// channel's light they held), when it is worth a word.
pub fn negative_note(share: f64) -> Option<String> {
    (share > 1e-3).then(|| {
        format!(
            "the PSF's negative samples (noise, the sub-pixel move; {:.2} % of its light) were \
             set to 0",
            100.0 * share
        )
    })
}

/// A real capture as restoration takes it.
pub struct Capture {
    /// Its planes (1 grey or 3 R, G, B) on its `[0, 1]` scale.
    pub planes: Vec<Array2<f64>>,
    /// Whether its levels are display-encoded (an 8-bit file), not linear in the light.
    pub display_encoded: bool,
}

/// A capture's planes on its `[0, 1]` scale: photos as `restore` reads them; `.npy` and
/// `.mat` arrays as they are (float) or over their full scale (integers). What the reader
/// noticed goes to `notes`, with a word when the levels are display-encoded.
///
/// # Errors
/// A file that does not read as a photo or an array.
pub fn load_capture(path: &Path, notes: &mut Vec<String>) -> Result<Capture> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    if ext == "npy" || ext == "mat" {
        let f = read_frame(path, &FramePick::default())?;
        notes.extend(f.notes.iter().map(|n| format!("{}: {n}", path.display())));
        let scale = f.full_scale.map_or(1.0, |s| 1.0 / s);
        return Ok(Capture {
            planes: f.planes.into_iter().map(|p| p * scale).collect(),
            display_encoded: false,
        });
    }
    let planes = udc_io::photo::load_photo::<f64>(path, None)?;
    let display_encoded = read_frame(path, &FramePick::default())
        .map(|f| f.encoding == Encoding::Gamma8)
        .unwrap_or(false);
    if display_encoded {
        notes.push(format!(
            "{}: the capture is 8-bit: its levels are display-encoded, not linear",
            path.display()
        ));
    }
    Ok(Capture {
        planes,
        display_encoded,
    })
}

/// Runs `restore --psf FILE --image CAPTURE`.
///
/// # Errors
/// A PSF set or capture that does not read, a capture with another number of channels than
/// the set can serve, a truth of another size, a bad σ² or method setting, unwritable outputs.
pub fn restore_measured(args: &MeasuredRun<'_>, progress: &Progress) -> Result<Report> {
    let psf_path = args.psf;
    let set = read_psf_set(psf_path, &SetDefaults::default())
        .with_context(|| format!("--psf {}", psf_path.display()))?;
    let mut notes = Vec::new();
    let capture = load_capture(args.image, &mut notes)?.planes;
    let n = capture.len();
    let (kernels, negative) = set.restoration_kernels(n).context("--psf")?;
    let psfs: Vec<&Array2<f64>> = kernels.iter().collect();
    if let Some(note) = negative_note(negative) {
        notes.push(note);
    }
    let sigma2 = match (args.denoise.denoise, args.denoise.denoise_sigma2) {
        (DenoiseMethod::None, _) => None,
        (DenoiseMethod::Bm3d, Some(Sigma2Arg::Value(v))) => Some(v),
        (DenoiseMethod::Bm3d, Some(other)) => bail!(
            "--denoise-sigma2 {other}: a real capture's noise is not simulated here; give its \
             variance at white as a number (or --denoise none)"
        ),
        (DenoiseMethod::Bm3d, None) => {
            notes.push(
                "not denoised: a real capture's noise variance is not known here (give \
                 --denoise-sigma2 S for BM3D)"
                    .into(),
            );
            None
        }
    };
    let (method, method_name) = args.method;
    let padding = args.padding;
    let truth = match args.truth {
        Some(t) => {
            let planes = load_capture(t, &mut notes)?.planes;
            if planes.len() != n
                || planes.first().map(Array2::dim) != capture.first().map(Array2::dim)
            {
                bail!(
                    "--truth {}: {} planes of {:?}, the capture has {n} of {:?}",
                    t.display(),
                    planes.len(),
                    planes.first().map(Array2::dim),
                    capture.first().map(Array2::dim)
                );
            }
            Some(planes)
        }
        None => None,
    };
    let restored = restore_capture(capture.clone(), &psfs, method, padding, sigma2, progress)?;
    let scores = match &truth {
        Some(t) => Some((
            quality::psnr_db_planes(&restored, t, 1.0)?,
            quality::psnr_db_planes(&capture, t, 1.0)?,
            restored
                .iter()
                .zip(t)
                .map(|(a, b)| quality::ssim(a.view(), b.view()))
                .collect::<Result<Vec<f64>, _>>()?,
        )),
        None => None,
    };
    let mut files = Vec::new();
    if let Some(dir) = args.out {
        let stem = args
            .image
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("capture");
        files = udc_io::display::restore_report::write_stage_images(
            dir,
            stem,
            udc_core::restore::Intermediate::Captured,
            &capture,
        )?;
        let truth_or_capture = truth.as_ref().unwrap_or(&capture);
        files.extend(udc_io::display::restore_report::write_restored_images(
            dir,
            stem,
            truth_or_capture,
            &restored,
        )?);
        if args.figures {
            use udc_io::display::restore_report::write_stage_figure;
            let difference =
                udc_core::restore::figures::difference_planes(&restored, truth_or_capture);
            for (name, planes) in [
                ("captured", &capture),
                ("restored", &restored),
                ("difference", &difference),
            ] {
                files.extend(write_stage_figure(dir, stem, name, planes)?);
            }
        }
    }
    let mut out = Report::default();
    let (rows, cols) = capture.first().map_or((0, 0), Array2::dim);
    outln!(
        out,
        "capture {} ({cols}×{rows}, {n} channel{}) restored with the {} PSF {} ({} px at {} µm, {} channel{})",
        args.image.display(),
        if n == 1 { "" } else { "s" },
        match set.source {
            udc_core::measured::PsfSource::Measured => "measured",
            udc_core::measured::PsfSource::Simulated => "simulated",
        },
        psf_path.display(),
        set.side_px(),
        set.pixel_um,
        set.channels.len(),
        if set.channels.len() == 1 { "" } else { "s" },
    );
    if let Some((psnr, captured_psnr, ssim)) = &scores {
        let mean_ssim = ssim.iter().sum::<f64>() / ssim.len().max(1) as f64;
        outln!(
            out,
            "PSNR {psnr:.2} dB (the capture {captured_psnr:.2} dB), SSIM {mean_ssim:.4}"
        );
    }
    for n in &notes {
        outln!(out, "note: {n}");
    }
    for f in &files {
        outln!(out, "wrote {}", f.display());
    }
    out.json = json!({
        "capture": args.image,
        "psf": psf_path,
        "psf_source": set.source,
        "pixel_um": set.pixel_um,
        "psf_side_px": set.side_px(),
        "method": method_name,
        "denoise_sigma2": sigma2,
        "psnr_db": scores.as_ref().map(|s| s.0),
        "captured_psnr_db": scores.as_ref().map(|s| s.1),
        "ssim": scores.as_ref().map(|s| s.2.clone()),
        "notes": notes,
        "files": files,
    });
    Ok(out)
}
