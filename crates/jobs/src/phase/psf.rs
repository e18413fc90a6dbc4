//! `phase psf`: PSFs, MTFs and invertibility of one design against the bare T-OLED.

use super::*;

/// The design `phase psf` computes: the mask's, its λ0 plan resolved (`optimized` runs the
/// allocation first) and the surface it asks for. A sweep row's design opens through it.
///
/// # Errors
/// Bad values (naming the flag), an unreadable response, cancellation.
pub fn psf_design(a: &PsfJob, progress: &Progress) -> Result<PhaseDesign> {
    psf_design_on(a, None, progress)
}

/// [`psf_design`], an `optimized` plan's V through `relay` where one is given.
fn psf_design_on(
    a: &PsfJob,
    relay: Option<&Arc<dyn BlochRelay>>,
    progress: &Progress,
) -> Result<PhaseDesign> {
    let mut design = design_of(&a.mask)?;
    let sampling = sampling_of(&a.mask);
    design.lambda0 = resolve_lambda0(
        &a.lambda0,
        &design,
        &sampling,
        a.spectral.as_deref(),
        relay,
        progress,
    )?;
    if a.unfolded {
        design.surface = Surface::Unfolded;
    }
    design
        .validate()
        .map_err(|e| anyhow::anyhow!("{}", e.to_string().replace("`lambda0.nm`", "--lambda0")))?;
    Ok(design)
}

/// Runs `phase psf`.
///
/// # Errors
/// Bad values (naming the flag), an unreadable response, unwritable outputs, cancellation.
pub fn psf(a: &PsfJob, progress: &Progress) -> Result<Report> {
    let mut out = Report::default();
    if !a.angle_deg.is_finite() || a.angle_deg.abs() >= 89.0 {
        bail!(
            "--angle-deg {:?}: must be a finite angle within ±89°",
            a.angle_deg
        );
    }
    let (route, relay) = relay_of(a.backend)?;
    let design = psf_design_on(a, relay.as_ref(), progress)?;
    let sampling = sampling_of(&a.mask);
    let channels = match &a.spectral {
        Some(p) => grid_channels(Some(p))?,
        None => Channel::rgb_peaks(),
    };
    let optics = if a.single_mask {
        PhaseOptics::SingleMask
    } else {
        PhaseOptics::DoubleMla
    };
    let incidence = Incidence::AngleDeg(a.angle_deg);
    let chain = chain_on(&design, &sampling, relay.as_ref())?;
    let psfs = {
        let p = progress;
        phase_psfs_on(&chain, &channels, optics, incidence, p)
    }?;
    let mut outputs = Vec::new();
    if let Some(dir) = &a.mask.out {
        std::fs::create_dir_all(dir).with_context(|| format!("create {}", dir.display()))?;
        let path = dir.join("psf.csv");
        let mut text = String::from("pixel_offset");
        for c in &psfs.channels {
            text.push_str(&format!(",{0},toled_{0}", c.name));
        }
        text.push('\n');
        let p = design.camera.pixels as i64;
        for k in 0..design.camera.pixels {
            text.push_str(&(k as i64 - p / 2).to_string());
            for c in &psfs.channels {
                text.push_str(&format!(",{:e},{:e}", c.psf[k], c.toled_psf[k]));
            }
            text.push('\n');
        }
        udc_io::safe_file::write_atomic(&path, text.as_bytes())?;
        outputs.push(path);
        if a.all_angles {
            for c in &channels {
                let k = {
                    let p = progress;
                    kernel_matrix_on(&chain, c, optics, p)
                }?;
                let path = dir.join(format!("kernels_{}.csv", c.name));
                let mut text = String::with_capacity(k.len() * 12);
                for row in k.rows() {
                    let line: Vec<String> = row.iter().map(|v| format!("{v:e}")).collect();
                    text.push_str(&line.join(","));
                    text.push('\n');
                }
                udc_io::safe_file::write_atomic(&path, text.as_bytes())?;
                outputs.push(path);
            }
        }
    }
    if let Some(dir) = &a.mask.out {
        outputs.extend(write_psf_figures(dir, &psfs, optics)?);
    }
    let lambda0 = lambda0_per_lenslet(&design)?;
    {
        let channels_json: Vec<Value> = psfs
            .channels
            .iter()
            .map(|c| {
                json!({
                    "name": c.name,
                    "wavelength_nm": r(c.wavelength_nm),
                    "energy_vs_toled": r(c.energy_vs_toled),
                    "energy_vs_toled_before_polariser": r(c.energy_vs_toled_before_polariser),
                    "peak": r(c.peak),
                    "invertibility": r(c.invertibility),
                    "transmission": r(c.transmission),
                    "toled_peak": r(c.toled_peak),
                    "toled_invertibility": r(c.toled_invertibility),
                    "toled_transmission": r(c.toled_transmission),
                    "psf": c.psf.iter().map(|&v| r(v)).collect::<Vec<_>>(),
                    "toled_psf": c.toled_psf.iter().map(|&v| r(v)).collect::<Vec<_>>(),
                })
            })
            .collect();
        let v = json!({
            "pitch_um": design.pitch_um,
            "fold": design.fold,
            "f_mla_um": design.f_mla_um,
            "surface": if a.unfolded { "unfolded" } else { "folded" },
            "optics": if a.single_mask { "single-mask" } else { "double-mla" },
            "lenslets": psfs.lenslets,
            "lambda0_nm": lambda0,
            "angle_deg": r(psfs.angle_deg),
            "image_pixel": psfs.image_pixel,
            "kappa": r(design.kappa()),
            "fov_deg": r(design.fov_deg()),
            "ltr_with_polariser": r(psfs.ltr_with_polariser),
            "ltr_min_with_polariser": r(0.5 * design.ltr_min()),
            "toled_ltr": r(psfs.toled_ltr),
            "channels": channels_json,
            "outputs": outputs.iter().map(|p| p.display().to_string()).collect::<Vec<_>>(),
        });
        out.json = v;
    }
    {
        outln!(
            out,
            "double MLA, pitch {} µm, T = {}, {} lenslets, λ0 {}–{} nm, angle {:.2}°",
            design.pitch_um,
            design.fold,
            psfs.lenslets,
            lambda0.iter().copied().fold(f64::INFINITY, f64::min),
            lambda0.iter().copied().fold(0.0, f64::max),
            psfs.angle_deg
        );
        outln!(
            out,
            "κ {:.2}  FoV {:.1}°  LTR {:.1} % (T-OLED {:.1} %, at the FoV edge {:.1} %)",
            design.kappa(),
            design.fov_deg(),
            100.0 * psfs.ltr_with_polariser,
            100.0 * psfs.toled_ltr,
            50.0 * design.ltr_min()
        );
        outln!(
            out,
            "channel  λ nm   energy vs T-OLED   peak (T-OLED)      invertibility (T-OLED)"
        );
        for c in &psfs.channels {
            outln!(
                out,
                "{:<7} {:5.0}   {:5.2}× ({:4.2}× before ½)   {:.4} ({:.4})   {:7.2} ({:7.2})",
                c.name,
                c.wavelength_nm,
                c.energy_vs_toled,
                c.energy_vs_toled_before_polariser,
                c.peak,
                c.toled_peak,
                c.invertibility,
                c.toled_invertibility
            );
        }
        for p in &outputs {
            outln!(out, "wrote {}", p.display());
        }
    }
    crate::backend::report(&mut out, a.backend, &route);
    Ok(out)
}

/// The studio's PSF and MTF plots as figures (SVG and PNG) in `dir`: `psf-<channel>` on a log
/// scale within [`figures::PSF_HALF_WIDTH_PX`] of the image point, and `mtf`.
fn write_psf_figures(
    dir: &Path,
    psfs: &udc_core::phase::psf::PhasePsfs,
    optics: PhaseOptics,
) -> Result<Vec<PathBuf>> {
    use udc_core::phase::figures;
    let ours = figures::optics_label(optics);
    let half = figures::PSF_HALF_WIDTH_PX as i64 + psfs.image_pixel.abs();
    let mut written = Vec::new();
    for (i, c) in psfs.channels.iter().enumerate() {
        let stem = c.name.replace(|ch: char| !ch.is_ascii_alphanumeric(), "-");
        let panel = figures::psf_panel(c, i, ours, half, true);
        written.extend(udc_io::figure::write_panel(
            dir,
            &format!("psf-{stem}"),
            &panel,
        )?);
    }
    let panel = figures::mtf_panel(psfs, ours);
    written.extend(udc_io::figure::write_panel(dir, "mtf", &panel)?);
    Ok(written)
}
