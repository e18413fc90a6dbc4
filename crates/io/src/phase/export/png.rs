//! The height profile as a 16-bit PNG.

use super::*;

/// Writes a 16-bit grayscale height map for grayscale lithography: one column per x sample,
/// `rows` identical rows (the plate is uniform along y). A pixel value times `um_per_level`
/// (tEXt chunk) is the height: `um_per_level` is the fabrication step when there is one, so
/// values are level numbers, else the tallest height over 65535. The pixel size is in the
/// `pixel_um` tEXt chunk and in `pHYs` (rounded to whole pixels per metre).
///
/// # Errors
/// Names `sample_um` or `rows` when out of range or the image would be too large, and
/// `height_step_um` when the levels do not fit 16 bits; [`IoError::Image`] when encoding fails.
pub fn write_height_png(
    design: &PhaseDesign,
    path: &Path,
    sample_um: f64,
    rows: usize,
    min_feature_um: f64,
) -> Result<ExportSummary, IoError> {
    let lenslets = lenslets_of(design)?;
    check_sample(design, sample_um)?;
    if rows == 0 || rows > MAX_PNG_ROWS {
        return Err(invalid(format!(
            "rows = {rows}: must be within 1–{MAX_PNG_ROWS}"
        )));
    }
    let columns = (MAX_PNG_WIDTH, "PNG width");
    let s = sample_profile(design, &lenslets, sample_um, columns, min_feature_um)?;
    let width = s.x_um.len();
    let pixels = width as u64 * rows as u64;
    if pixels > MAX_PNG_PIXELS {
        return Err(invalid(format!(
            "rows = {rows}: {width} × {rows} is {pixels} pixels, more than {MAX_PNG_PIXELS}; \
             use fewer rows or a coarser sample_um"
        )));
    }
    let max_height = max_of(s.height_um.iter().copied());
    let um_per_level = match design.height_step_um {
        Some(step) => {
            let top = (max_height / step).round();
            if top > 65535.0 {
                return Err(invalid(format!(
                    "height_step_um = {step}: the plate has {top} levels above 0, more than a \
                     16-bit PNG holds (65535); use a coarser step"
                )));
            }
            step
        }
        None => {
            let tallest = lenslets.max_height_um(design);
            if tallest > 0.0 {
                tallest / 65535.0
            } else {
                1.0
            }
        }
    };
    let row: Vec<u8> = s
        .height_um
        .iter()
        .flat_map(|&h| {
            let level = (h / um_per_level).round().clamp(0.0, 65535.0) as u16;
            level.to_be_bytes()
        })
        .collect();
    let levels = design
        .height_step_um
        .map(|_| (max_height / um_per_level).round() as usize + 1);
    let description = format!(
        "UDC Studio phase-plate height map (thesis 4.6). height_um = pixel value x um_per_level. \
         Columns: x across the lenslets, pixel_um apart, centred on the optical axis; rows are \
         identical (the plate is uniform along y). {}",
        header_lines(design, &lenslets)[2..].join("; ")
    );
    let bytes = encode_png(
        path,
        (width, rows),
        &row,
        &[
            ("um_per_level", format!("{um_per_level}")),
            ("pixel_um", format!("{sample_um}")),
            ("description", description),
            ("Software", "UDC Studio".into()),
        ],
        sample_um,
    )?;
    write_atomic(path, &bytes)?;
    let mut summary = ExportSummary::new(path, HeightFormat::Png, lenslets.span_um(), max_height);
    summary.samples = Some(width);
    summary.sample_um = Some(sample_um);
    summary.pixel_um = Some(sample_um);
    summary.rows = Some(rows);
    summary.levels = levels;
    summary.um_per_level = Some(um_per_level);
    Ok(summary)
}

/// The PNG bytes. Identical rows are streamed, so memory stays at one row plus the (tiny)
/// compressed image.
fn encode_png(
    path: &Path,
    (width, rows): (usize, usize),
    row: &[u8],
    texts: &[(&str, String)],
    pixel_um: f64,
) -> Result<Vec<u8>, IoError> {
    let err = |e: String| IoError::Image {
        path: path.to_path_buf(),
        message: format!("cannot encode the PNG: {e}"),
    };
    let to_u32 = |v: usize| u32::try_from(v).map_err(|e| err(e.to_string()));
    let mut bytes = Vec::new();
    let mut enc = Encoder::new(&mut bytes, to_u32(width)?, to_u32(rows)?);
    enc.set_color(ColorType::Grayscale);
    enc.set_depth(BitDepth::Sixteen);
    let ppm = (1e6 / pixel_um).round().clamp(1.0, f64::from(u32::MAX)) as u32;
    enc.set_pixel_dims(Some(PixelDimensions {
        xppu: ppm,
        yppu: ppm,
        unit: Unit::Meter,
    }));
    for (key, text) in texts {
        enc.add_text_chunk((*key).into(), text.clone())
            .map_err(|e| err(e.to_string()))?;
    }
    let mut writer = enc.write_header().map_err(|e| err(e.to_string()))?;
    {
        let mut stream = writer.stream_writer().map_err(|e| err(e.to_string()))?;
        for _ in 0..rows {
            stream.write_all(row).map_err(|e| err(e.to_string()))?;
        }
        stream.finish().map_err(|e| err(e.to_string()))?;
    }
    writer.finish().map_err(|e| err(e.to_string()))?;
    Ok(bytes)
}
