//! The height profile as CSV.

use super::*;

/// The CSV text of [`write_height_csv`]: a `#` header stating units and design, then
/// `x_um,height_um,lenslet,lambda0_nm` rows. Positions and heights are rounded to
/// [`CSV_DECIMALS`] decimals (1e-9 µm) and written as shortest round-trip decimals: a reader
/// recovers the model's heights to 1e-9 µm, without float noise (0.6, not 0.6000000000000001).
///
/// # Errors
/// A message naming `sample_um` when it is out of range or gives too many rows, or the design's
/// own validation error.
pub fn height_csv_text(
    design: &PhaseDesign,
    sample_um: f64,
    min_feature_um: f64,
) -> Result<String, IoError> {
    Ok(csv_text(design, sample_um, min_feature_um)?.0)
}

fn csv_text(
    design: &PhaseDesign,
    sample_um: f64,
    min_feature_um: f64,
) -> Result<(String, Samples), IoError> {
    let lenslets = lenslets_of(design)?;
    check_sample(design, sample_um)?;
    let rows = (MAX_CSV_SAMPLES, "CSV export");
    let s = sample_profile(design, &lenslets, sample_um, rows, min_feature_um)?;
    let mut out = String::with_capacity(64 * s.x_um.len() + 1024);
    for line in header_lines(design, &lenslets) {
        out.push_str("# ");
        out.push_str(&line);
        out.push('\n');
    }
    out.push_str(&format!(
        "# samples: {} every {sample_um} um, x_i = (i - (N-1)/2) * sample_um\n",
        s.x_um.len()
    ));
    out.push_str("x_um,height_um,lenslet,lambda0_nm\n");
    for (&x, &h) in s.x_um.iter().zip(&s.height_um) {
        let h = crate::numbers::snap_decimals(h, CSV_DECIMALS);
        match lenslets.locate(x) {
            Some((l, _)) => {
                let lambda = lenslets.lambda0_nm.get(l).copied().unwrap_or(f64::NAN);
                out.push_str(&format!("{x},{h},{l},{lambda}\n"));
            }
            None => out.push_str(&format!("{x},{h},,\n")),
        }
    }
    Ok((out, s))
}

/// Writes the height profile as CSV (see [`height_csv_text`]), for plotting and for checking
/// a fabricated plate against the design with a profilometer.
///
/// # Errors
/// As [`height_csv_text`], or when the file cannot be written.
pub fn write_height_csv(
    design: &PhaseDesign,
    path: &Path,
    sample_um: f64,
    min_feature_um: f64,
) -> Result<ExportSummary, IoError> {
    let (text, s) = csv_text(design, sample_um, min_feature_um)?;
    write_atomic(path, text.as_bytes())?;
    let width = geometry::lenslet_count(design) as f64 * design.pitch_um;
    let mut summary = ExportSummary::new(
        path,
        HeightFormat::Csv,
        width,
        max_of(s.height_um.iter().copied()),
    );
    summary.samples = Some(s.x_um.len());
    summary.sample_um = Some(sample_um);
    Ok(summary)
}

/// Writes a blur matrix (rows: sensor pixels, columns: directions) as CSV in scientific
/// notation, streamed to a temporary file beside `path` and renamed into place.
///
/// # Errors
/// When the file cannot be written.
pub fn write_kernels_csv(k: &ndarray::Array2<f64>, path: &Path) -> Result<(), IoError> {
    let fail = |e| IoError::file("write", path, e);
    let temp = TempFile::beside(path)?;
    let file = crate::safe_file::open_reserved(temp.path()).map_err(fail)?;
    let mut w = std::io::BufWriter::new(file);
    for row in k.rows() {
        for (j, v) in row.iter().enumerate() {
            if j > 0 {
                w.write_all(b",").map_err(fail)?;
            }
            write!(w, "{v:e}").map_err(fail)?;
        }
        w.write_all(b"\n").map_err(fail)?;
    }
    w.flush().map_err(fail)?;
    drop(w);
    temp.persist()
}
