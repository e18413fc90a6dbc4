//! `phase restore`: photos captured through the masks and restored, one setup or the thesis's comparison.

use super::*;

fn restore_photos(paths: &[PathBuf], pixels: usize) -> Result<Vec<(String, Vec<Array2<f64>>)>> {
    if paths.is_empty() {
        return Ok(vec![(
            udc_io::photo::BUILT_IN_PHOTO_NAME.to_string(),
            udc_io::photo::fit_max_side(udc_io::photo::built_in_photo()?, pixels),
        )]);
    }
    paths
        .iter()
        .map(|p| {
            Ok((
                p.display().to_string(),
                udc_io::photo::load_photo(p, Some(pixels as u32))?,
            ))
        })
        .collect()
}

/// Runs `phase restore`: one setup, or the thesis's comparison (`--compare`).
///
/// # Errors
/// Bad values (naming the flag), unreadable photos, unwritable outputs, cancellation.
pub fn restore(a: &RestoreJob, progress: &Progress) -> Result<Report> {
    let mut out = Report::default();
    use udc_core::phase::imaging::{Lambda0Plan, LensletOrder, Setup, capture_and_restore};
    let denoise = a.denoise.resolve(udc_core::restore::Recipe::Iccv23)?;
    let (route, relay) = relay_of(a.backend)?;
    let base = design_of(&a.mask)?;
    let sampling = sampling_of(&a.mask);
    for &n in &a.photons {
        let (lo, hi) = udc_core::phase::imaging::PHOTONS_RANGE;
        if !(n.is_finite() && (lo..=hi).contains(&n)) {
            bail!("--photons {n:?}: must be {lo} … {hi} photons per pixel");
        }
    }
    if let Some(q) = a.quantize_um
        && !(q.is_finite() && (0.001..=10.0).contains(&q))
    {
        bail!("--quantize-um {q:?}: must be 0.001 … 10 µm");
    }
    let setup = if a.bare {
        Setup::Bare {
            pitch_um: base.pitch_um,
        }
    } else {
        let lambda0 = match parse_lambda0(&a.lambda0)? {
            Some(Lambda0::Fixed { nm }) => Lambda0Plan::Fixed { nm },
            Some(_) => Lambda0Plan::Uniform,
            None => Lambda0Plan::Optimized,
        };
        Setup::DoubleMla {
            pitch_um: base.pitch_um,
            fold: base.fold,
            lambda0,
            order: match a.order {
                OrderArg::Ascending => LensletOrder::Ascending,
                OrderArg::Shuffled => LensletOrder::Shuffled { seed: a.seed },
            },
            quantize_um: a.quantize_um.or(base.height_step_um),
        }
    };
    let pixels = base.camera.pixels;
    if let Some(n) = a.scene_px
        && !(8..=pixels).contains(&n)
    {
        bail!("--scene-px {n}: must be 8 … {pixels} columns (the sensor's pixels)");
    }
    let mut photos = restore_photos(&a.photo, pixels)?;
    if let Some(n) = a.scene_px {
        for (_, planes) in &mut photos {
            *planes = udc_io::photo::scale_to_width(std::mem::take(planes), n);
        }
    }
    if a.full_boundary && a.compare {
        bail!("--full-boundary: not with --compare (one setup at a time)");
    }
    if a.compare {
        let mut out = compare(a, denoise, (&base, &sampling), &photos, relay, progress)?;
        crate::backend::report(&mut out, a.backend, &route);
        return Ok(out);
    }
    if photos.len() > 1 {
        bail!("one --photo per run (several go with --compare)");
    }
    let (photo_name, photo) = photos.remove(0);
    let width = photo.first().map_or(0, ndarray::Array2::ncols);
    // Thesis §4.4.1's 'full' boundary: as many directions again beyond the scene, half on each
    // side (its estimate is 2048 columns for a 1024-column capture).
    let margin = if a.full_boundary { width / 2 } else { 0 };
    let grid = grid_channels(None)?;
    let channels = if a.peaks {
        Channel::rgb_peaks()
    } else {
        grid.clone()
    };
    // Shared with a sweep's other points on this setup (Algorithm 1 and V run once).
    let (design, optics) = {
        let p = progress;
        super::design_cache::resolve_shared(&setup, &base, &sampling, &grid, relay.as_ref(), p)
    }?;
    let blur = {
        let p = progress;
        let (c, s) = (&channels, &sampling);
        super::design_cache::blur_shared(&design, s, c, optics, width, margin, relay, p)
    }?;
    let mut runs = Vec::new();
    let mut written = Vec::new();
    for &n in &a.photons {
        let run = {
            let p = progress;
            capture_and_restore(&blur, &photo, n, a.seed, denoise, p)
        }?;
        if let Some(dir) = &a.mask.out {
            let stem = format!("{}photons", n.round());
            written.extend(udc_io::display::restore_report::write_capture_images(
                dir,
                &stem,
                &photo,
                &udc_io::display::restore_report::CaptureImages {
                    captured: &run.captured,
                    denoised: &run.denoised,
                    restored: &run.restored,
                },
            )?);
        }
        runs.push(run);
    }
    let valid = blur.valid.clone();
    let unpassed_mse = udc_core::phase::imaging::unpassed_mse(&blur, &photo)?;
    {
        out.json = json!({
            "setup": setup,
            "label": setup.label(),
            "sampling": design.sampling.name(),
            "relay": sampling.relay_for(&design, optics).name(),
            "channels": if a.peaks { "peaks" } else { "spectral" },
            "photo": photo_name,
            "width_px": width,
            "boundary": if margin > 0 { "full" } else { "scene" },
            "ltr": r(blur.ltr),
            "fov_deg": r(design.fov_deg()),
            "valid_columns": [valid.start, valid.end],
            "unpassed_mse": r(unpassed_mse),
            "denoise": {"method": denoise.method_name()},
            "runs": runs.iter().map(|x| json!({
                "photons": x.photons,
                "psnr_db": r(x.psnr_db),
                "ssim": r(x.ssim),
                "captured_psnr_db": r(x.captured_psnr_db),
                "denoised_psnr_db": x.denoised_psnr_db.map_or(Value::Null, r),
                "denoise": udc_io::display::restore_report::denoise_json(&x.denoise),
                "cg": {"lambda": r(x.cg.lambda), "iterations": x.cg.iterations, "tolerance": x.cg.tolerance},
            })).collect::<Vec<_>>(),
            "written": written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>(),
        });
    }
    {
        outln!(
            out,
            "{}: LTR {:.3}, FoV {:.1}°, scored on columns {}..{} of {width}{}",
            setup.label(),
            blur.ltr,
            design.fov_deg(),
            valid.start,
            valid.end,
            if margin > 0 {
                format!(
                    " (restored over {} columns and cropped)",
                    width + 2 * margin
                )
            } else {
                String::new()
            }
        );
        if unpassed_mse > 0.0 {
            outln!(
                out,
                "the photo without the frequencies this setup passes < 1 % of: {:.2} dB",
                -10.0 * unpassed_mse.log10()
            );
        }
        outln!(
            out,
            "{:>10}  {:>9}  {:>6}  {:>12}  {:>12}",
            "photons",
            "PSNR dB",
            "SSIM",
            "capture dB",
            "denoised dB"
        );
        for x in &runs {
            let denoised = x
                .denoised_psnr_db
                .map_or_else(|| "-".to_string(), |p| format!("{p:.2}"));
            outln!(
                out,
                "{:>10}  {:>9.2}  {:>6.3}  {:>12.2}  {denoised:>12}  {}, CG λ {}",
                x.photons,
                x.psnr_db,
                x.ssim,
                x.captured_psnr_db,
                crate::denoise::denoise_text(&x.denoise),
                x.cg.lambda
            );
        }
        for p in &written {
            outln!(out, "wrote {}", p.display());
        }
    }
    crate::backend::report(&mut out, a.backend, &route);
    Ok(out)
}

fn compare(
    a: &RestoreJob,
    denoise: udc_core::restore::Denoise,
    (base, sampling): (&PhaseDesign, &PhaseSampling),
    photos: &[(String, Vec<Array2<f64>>)],
    relay: Option<Arc<dyn BlochRelay>>,
    progress: &Progress,
) -> Result<Report> {
    let mut out = Report::default();
    use udc_core::phase::imaging::{CompareRow, compare_setups, thesis_setups};
    let setups = thesis_setups();
    let grid = grid_channels(None)?;
    let channels = if a.peaks {
        Channel::rgb_peaks()
    } else {
        grid.clone()
    };
    let planes: Vec<Vec<Array2<f64>>> = photos.iter().map(|(_, p)| p.clone()).collect();
    let mut rows: Vec<CompareRow> = Vec::new();
    {
        let p = progress;
        compare_setups(
            base,
            sampling,
            &setups,
            &grid,
            &channels,
            &planes,
            &a.photons,
            a.seed,
            denoise,
            relay.as_ref(),
            p,
            |row| rows.push(row),
        )
    }?;
    if let Some(dir) = &a.mask.out {
        std::fs::create_dir_all(dir).with_context(|| format!("create {}", dir.display()))?;
        let names: Vec<String> = photos.iter().map(|(n, _)| n.clone()).collect();
        let text = udc_io::display::restore_report::compare_csv(&rows, &names);
        let path = dir.join("compare.csv");
        udc_io::safe_file::write_atomic(&path, text.as_bytes())?;
        outln!(out, "wrote {}", path.display());
    }
    // Means over photos, per setup and light level, then over light levels.
    let mut summary = Vec::new();
    for setup in &setups {
        let mine: Vec<&CompareRow> = rows.iter().filter(|r| &r.setup == setup).collect();
        let mean = |f: &dyn Fn(&CompareRow) -> f64, rs: &[&CompareRow]| {
            rs.iter().map(|r| f(r)).sum::<f64>() / rs.len().max(1) as f64
        };
        let per_level: Vec<Value> = a
            .photons
            .iter()
            .map(|&n| {
                let at: Vec<&CompareRow> = mine.iter().copied().filter(|r| r.photons == n).collect();
                let denoised: Vec<f64> = at.iter().filter_map(|x| x.denoised_psnr_db).collect();
                let denoised_psnr_db = if denoised.is_empty() {
                    Value::Null
                } else {
                    r(denoised.iter().sum::<f64>() / denoised.len() as f64)
                };
                json!({"photons": n, "psnr_db": r(mean(&|x| x.psnr_db, &at)), "ssim": r(mean(&|x| x.ssim, &at)), "denoised_psnr_db": denoised_psnr_db})
            })
            .collect();
        summary.push(json!({
            "setup": setup,
            "label": setup.label(),
            "ltr": r(mine.first().map_or(0.0, |x| x.ltr)),
            "psnr_db": r(mean(&|x| x.psnr_db, &mine)),
            "ssim": r(mean(&|x| x.ssim, &mine)),
            "unpassed_mse": r(mean(&|x| x.unpassed_mse, &mine)),
            "runs": per_level,
        }));
    }
    {
        out.json = json!({"sampling": base.sampling.name(), "relay": sampling.relay.name(), "photos": photos.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>(), "denoise": denoise_summary(denoise, &a.photons), "setups": summary});
    }
    {
        out!(out, "{:<42} {:>6}", "setup (mean over photos)", "LTR");
        for n in &a.photons {
            out!(out, " {:>13}", format!("{n} ph"));
        }
        outln!(out, " {:>13} {:>9}", "mean", "unpassed");
        for s in &summary {
            out!(
                out,
                "{:<42} {:>6.3}",
                s["label"].as_str().unwrap_or(""),
                s["ltr"].as_f64().unwrap_or(0.0)
            );
            for run in s["runs"].as_array().map_or(&[][..], Vec::as_slice) {
                out!(
                    out,
                    " {:>6.2} {:>6.3}",
                    run["psnr_db"].as_f64().unwrap_or(f64::NAN),
                    run["ssim"].as_f64().unwrap_or(f64::NAN)
                );
            }
            // The PSNR of the photos without what this setup passes < 1 % of, dB.
            let unpassed = s["unpassed_mse"]
                .as_f64()
                .filter(|m| *m > 0.0)
                .map_or_else(|| "-".to_string(), |m| format!("{:.2}", -10.0 * m.log10()));
            outln!(
                out,
                " {:>6.2} {:>6.3} {:>9}",
                s["psnr_db"].as_f64().unwrap_or(f64::NAN),
                s["ssim"].as_f64().unwrap_or(f64::NAN),
                unpassed
            );
        }
    }
    Ok(out)
}

/// The compare JSON's `"denoise"`: the method and, per light level, the σ² BM3D got. A table
/// or fixed σ² is the same in every setup (phase captures all read ≈ 1 at white); a matched σ²
/// follows each setup's LTR, so it is `null` here and given per run in `setups`.
fn denoise_summary(denoise: udc_core::restore::Denoise, photons: &[f64]) -> Value {
    use udc_core::restore::{Denoise, Sigma2};
    let matched = matches!(
        denoise,
        Denoise::Bm3d {
            sigma2: Sigma2::Matched
        }
    );
    let per_level: Vec<Value> = photons
        .iter()
        .map(|&n| {
            // The table's σ² needs no LTR; a matched one has none to give here.
            let used = (!matched)
                .then(|| denoise.applied(&udc_core::phase::imaging::capture_noise(n, 1.0)))
                .and_then(|u| u.ok()?.sigma2);
            json!({"photons": n, "sigma2": used.map_or(Value::Null, r)})
        })
        .collect();
    json!({"method": denoise.method_name(), "sigma2_source": if matched { Value::from("matched") } else { Value::Null }, "runs": per_level})
}
