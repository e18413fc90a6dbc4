//! Sensor spectral response tables (CSV) and the colour channels they define (conventions.md §2,
//! "a spectral mode takes a sensor response table").
//!
//! The table has four columns, wavelength in nm then the R, G and B responses:
//! ```text
//! wavelength_nm,r,g,b
//! 401,9.79432e-05,4.28284e-05,6.69792e-05
//! ```
//! The header row is optional. When present, its first column names the wavelength
//! (`wavelength`, `wavelength_nm`, `lambda`, `nm`) and the other three are `r`, `g`, `b` in any
//! order and case. Blank lines and lines starting with `#` are skipped.

use std::path::Path;

use crate::IoError;
use crate::error::{SpectralError, TableError};
use udc_core::design::{Channel, MAX_WAVELENGTHS};

/// Spectral tables larger than this are refused before parsing (a 1 nm table is ~12 kB).
pub const MAX_TABLE_BYTES: u64 = 16 * 1024 * 1024;

/// A sensor's spectral response, one row per wavelength (strictly increasing).
#[derive(Debug, Clone, PartialEq)]
pub struct SpectralResponse {
    /// Wavelength of each row, in nm, strictly increasing.
    pub wavelengths_nm: Vec<f64>,
    /// Red response at each wavelength (non-negative, any scale: channels are normalised).
    pub r: Vec<f64>,
    /// Green response at each wavelength (non-negative, any scale).
    pub g: Vec<f64>,
    /// Blue response at each wavelength (non-negative, any scale).
    pub b: Vec<f64>,
}

/// Reads a spectral response CSV.
///
/// # Errors
/// [`IoError::File`] when the file cannot be read; [`IoError::Table`] (a [`SpectralError`])
/// naming the line and column for a cell that is not a number, a NaN/infinite/negative value, a
/// wavelength that does not increase, a wrong number of columns, or a table of fewer than 2
/// rows.
pub fn load_response_csv(path: &Path) -> Result<SpectralResponse, IoError> {
    let text =
        crate::safe_file::read_text_bounded(path, MAX_TABLE_BYTES, "read the spectral table")?;
    parse_response_csv(&text).map_err(|e| IoError::Table {
        path: path.to_path_buf(),
        error: TableError::Spectral(e),
    })
}

/// Parses the text of a spectral response CSV (see [`load_response_csv`]).
///
/// # Errors
/// A [`SpectralError`] naming the line (1-based) and column (1-based) of the first problem.
pub fn parse_response_csv(text: &str) -> Result<SpectralResponse, SpectralError> {
    let mut resp = SpectralResponse {
        wavelengths_nm: Vec::new(),
        r: Vec::new(),
        g: Vec::new(),
        b: Vec::new(),
    };
    // Column index of r, g, b among the three response columns (1, 2, 3 without a header).
    let mut order = [1usize, 2, 3];
    let mut first_content = true;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.trim_start_matches('\u{feff}').trim();
        if content.is_empty() || content.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = content
            .split(',')
            .map(|f| f.trim().trim_matches('"').trim())
            .collect();
        if fields.len() != 4 {
            return Err(SpectralError::ColumnCount {
                line,
                found: fields.len(),
            });
        }
        let is_header = first_content && fields[0].parse::<f64>().is_err();
        first_content = false;
        if is_header {
            order = header_order(&fields, line)?;
            continue;
        }
        let mut values = [0.0; 4];
        for (col, (field, value)) in fields.iter().zip(values.iter_mut()).enumerate() {
            *value = number(field, line, col + 1)?;
        }
        let wavelength_nm = values[0];
        if wavelength_nm <= 0.0 {
            return Err(SpectralError::WavelengthNotPositive {
                line,
                wavelength_nm,
            });
        }
        if let Some(&previous_nm) = resp.wavelengths_nm.last()
            && wavelength_nm <= previous_nm
        {
            return Err(SpectralError::NotIncreasing {
                line,
                wavelength_nm,
                previous_nm,
            });
        }
        resp.wavelengths_nm.push(wavelength_nm);
        resp.r.push(values[order[0]]);
        resp.g.push(values[order[1]]);
        resp.b.push(values[order[2]]);
    }
    if resp.wavelengths_nm.len() < 2 {
        return Err(SpectralError::TooFewRows {
            rows: resp.wavelengths_nm.len(),
        });
    }
    Ok(resp)
}

/// A finite, non-negative number: the cell at `line`, `column`.
fn number(field: &str, line: usize, column: usize) -> Result<f64, SpectralError> {
    let value = || field.to_string();
    let v: f64 = field.parse().map_err(|_| SpectralError::NotANumber {
        line,
        column,
        value: value(),
    })?;
    if !v.is_finite() {
        return Err(SpectralError::NotFinite {
            line,
            column,
            value: value(),
        });
    }
    if v < 0.0 {
        return Err(SpectralError::Negative {
            line,
            column,
            value: value(),
        });
    }
    Ok(v)
}

/// Which value column (1..=3) holds r, g and b, from the names of the header at `line`.
fn header_order(fields: &[&str], line: usize) -> Result<[usize; 3], SpectralError> {
    let first = fields[0].to_ascii_lowercase();
    if !(first.starts_with("wavelength") || first.starts_with("lambda") || first == "nm") {
        return Err(SpectralError::WavelengthHeader {
            line,
            found: fields[0].to_string(),
        });
    }
    let mut order = [0usize; 3];
    for (slot, channel) in order.iter_mut().zip(["r", "g", "b"]) {
        let found: Vec<usize> = (1..4)
            .filter(|&c| fields[c].eq_ignore_ascii_case(channel))
            .collect();
        match found.as_slice() {
            [c] => *slot = *c,
            [] => return Err(SpectralError::MissingChannel { line, channel }),
            _ => return Err(SpectralError::DuplicateChannel { line, channel }),
        }
    }
    Ok(order)
}

impl SpectralResponse {
    /// The response curves in R, G, B order with their channel names.
    fn curves(&self) -> [(&'static str, &[f64]); 3] {
        [("R", &self.r), ("G", &self.g), ("B", &self.b)]
    }

    /// Linear interpolation of `values` (one per table row) at `wavelength_nm`; `None` outside
    /// the table. A table wavelength returns its row's value exactly.
    fn interpolate(&self, values: &[f64], wavelength_nm: f64) -> Option<f64> {
        let w = &self.wavelengths_nm;
        // Rows at or below the wavelength; the segment is [idx − 1, idx].
        let idx = w.partition_point(|&x| x <= wavelength_nm);
        if idx == 0 {
            return None;
        }
        let (w0, v0) = (w[idx - 1], *values.get(idx - 1)?);
        if w0 == wavelength_nm {
            return Some(v0);
        }
        let (w1, v1) = (*w.get(idx)?, *values.get(idx)?);
        let t = (wavelength_nm - w0) / (w1 - w0);
        Some(v0 + t * (v1 - v0))
    }
}

/// The multiples of `step_nm` inside the table's range `[lo_nm, hi_nm]`: the sample wavelengths
/// of `--spectral-step-nm`. Refused before anything is allocated when the step is not a
/// positive number or the grid would exceed [`MAX_WAVELENGTHS`].
///
/// # Errors
/// A [`SpectralError`] naming the step (and, when it is too fine, the smallest step that fits).
pub fn sample_grid(lo_nm: f64, hi_nm: f64, step_nm: f64) -> Result<Vec<f64>, SpectralError> {
    if !(step_nm.is_finite() && step_nm > 0.0) {
        return Err(SpectralError::StepNotPositive { step_nm });
    }
    let first = (lo_nm / step_nm).ceil() * step_nm;
    let count = ((hi_nm - first) / step_nm).floor() + 1.0;
    if !(count >= 1.0) {
        return Err(SpectralError::NoStepInRange {
            step_nm,
            lo_nm,
            hi_nm,
        });
    }
    if count > MAX_WAVELENGTHS as f64 {
        let min_step = (hi_nm - lo_nm) / (MAX_WAVELENGTHS - 1) as f64;
        return Err(SpectralError::TooManySamples {
            step_nm,
            count,
            lo_nm,
            hi_nm,
            min_step_nm: (min_step * 10.0).ceil() / 10.0,
        });
    }
    Ok((0..count as usize)
        .map(|k| first + k as f64 * step_nm)
        .collect())
}

/// Channels R, G, B sampled at `sample_wavelengths_nm`: each weight is the linearly interpolated
/// response at that wavelength, normalised so a channel's weights sum to 1.
///
/// # Errors
/// A [`SpectralError`] when no wavelength is given, a wavelength is not finite or lies outside
/// the table, or a channel's response is zero at every sample wavelength.
pub fn channels_from_response(
    resp: &SpectralResponse,
    sample_wavelengths_nm: &[f64],
) -> Result<Vec<Channel>, SpectralError> {
    if sample_wavelengths_nm.is_empty() {
        return Err(SpectralError::NoSamples);
    }
    let (lo_nm, hi_nm) = match (resp.wavelengths_nm.first(), resp.wavelengths_nm.last()) {
        (Some(lo), Some(hi)) => (*lo, *hi),
        _ => return Err(SpectralError::EmptyTable),
    };
    resp.curves()
        .into_iter()
        .map(|(channel, values)| {
            let weights = sample_wavelengths_nm
                .iter()
                .map(|&wavelength_nm| {
                    if !wavelength_nm.is_finite() {
                        return Err(SpectralError::SampleNotFinite { wavelength_nm });
                    }
                    resp.interpolate(values, wavelength_nm)
                        .ok_or(SpectralError::SampleOutside {
                            wavelength_nm,
                            lo_nm,
                            hi_nm,
                        })
                })
                .collect::<Result<Vec<f64>, SpectralError>>()?;
            let sum: f64 = weights.iter().sum();
            if !(sum > 0.0) {
                return Err(SpectralError::ZeroChannel { channel });
            }
            Ok(Channel {
                name: channel.into(),
                wavelengths_nm: sample_wavelengths_nm.to_vec(),
                weights: weights.iter().map(|w| w / sum).collect(),
            })
        })
        .collect()
}

/// The thesis's sensor response (`assets/spectral/thesis_sensor_response.csv`), built in so the
/// phase-mask optimizer works without a file.
pub fn thesis_response() -> SpectralResponse {
    const TEXT: &str = include_str!("../../../../assets/spectral/thesis_sensor_response.csv");
    // The table is a committed asset checked by the tests; a parse failure is a build defect.
    parse_response_csv(TEXT).unwrap_or_else(|e| panic!("built-in thesis response: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    const TABLE: &str = "wavelength_nm,r,g,b\n500,0.0,1,2\n510,1,3,2\n520,4,0,2\n";

    #[test]
    fn headerless_tables_are_read_in_column_order() {
        let r = parse_response_csv("500,1,2,3\n510,4,5,6\n").unwrap();
        assert_eq!(r.wavelengths_nm, vec![500.0, 510.0]);
        assert_eq!((r.r[1], r.g[1], r.b[1]), (4.0, 5.0, 6.0));
    }

    #[test]
    fn header_columns_may_come_in_any_order_and_case() {
        let r = parse_response_csv("Wavelength,B,R,G\r\n500,1,2,3\r\n510,4,5,6\r\n").unwrap();
        assert_eq!((r.r[0], r.g[0], r.b[0]), (2.0, 3.0, 1.0));
    }

    #[test]
    fn errors_name_line_and_column() {
        let e = parse_response_csv("wavelength_nm,r,g,b\n500,1,2,3\n510,1,x,3\n").unwrap_err();
        assert_eq!(e.to_string(), "line 3, column 3: `x` is not a number");
        let e = parse_response_csv("500,1,2,3\n510,1,NaN,3\n").unwrap_err();
        assert!(e.to_string().starts_with("line 2, column 3"), "{e}");
        let e = parse_response_csv("500,1,2,3\n510,1,2,-3\n").unwrap_err();
        assert!(e.to_string().starts_with("line 2, column 4"), "{e}");
        let e = parse_response_csv("500,1,2,3\n500,1,2,3\n").unwrap_err();
        assert!(e.to_string().starts_with("line 2, column 1"), "{e}");
        let e = parse_response_csv("500,1,2\n").unwrap_err();
        assert!(e.to_string().starts_with("line 1:"), "{e}");
        let e = parse_response_csv("wavelength_nm,r,g,b\n500,1,2,3\n").unwrap_err();
        assert!(e.to_string().contains("1 data row"), "{e}");
    }

    #[test]
    fn each_failure_mode_is_its_own_variant_with_its_position() {
        let err = |text: &str| parse_response_csv(text).unwrap_err();
        assert_eq!(
            err("# comment\n\nwavelength_nm,r,g,b\n500,1,2,3\n510,1,x,3\n"),
            SpectralError::NotANumber {
                line: 5,
                column: 3,
                value: "x".into()
            }
        );
        assert_eq!(
            err("500,1,2,3\n510,1,inf,3\n"),
            SpectralError::NotFinite {
                line: 2,
                column: 3,
                value: "inf".into()
            }
        );
        assert_eq!(
            err("500,1,2,3\n490,1,2,3\n"),
            SpectralError::NotIncreasing {
                line: 2,
                wavelength_nm: 490.0,
                previous_nm: 500.0
            }
        );
        assert_eq!(
            err("freq,r,g,b\n500,1,2,3\n"),
            SpectralError::WavelengthHeader {
                line: 1,
                found: "freq".into()
            }
        );
        assert_eq!(
            err("nm,r,r,b\n500,1,2,3\n"),
            SpectralError::DuplicateChannel {
                line: 1,
                channel: "r"
            }
        );
        assert_eq!(
            err("nm,r,x,b\n500,1,2,3\n"),
            SpectralError::MissingChannel {
                line: 1,
                channel: "g"
            }
        );
        assert_eq!(err("500,1,2,3\n"), SpectralError::TooFewRows { rows: 1 });
        // The header's messages keep their own "line N: column 1" form.
        assert_eq!(
            err("freq,r,g,b\n").to_string(),
            "line 1: column 1: header `freq` should name the wavelength (e.g. `wavelength_nm`)"
        );
    }

    #[test]
    fn sample_grid_refusals_carry_the_step() {
        assert_eq!(
            sample_grid(400.0, 700.0, 0.0),
            Err(SpectralError::StepNotPositive { step_nm: 0.0 })
        );
        assert!(matches!(
            sample_grid(401.0, 402.0, 5.0),
            Err(SpectralError::NoStepInRange { step_nm: 5.0, .. })
        ));
        let e = sample_grid(400.0, 700.0, 1.0).unwrap_err();
        assert!(
            matches!(e, SpectralError::TooManySamples { count, min_step_nm, .. }
                if count == 301.0 && min_step_nm == 2.4),
            "{e:?}"
        );
        assert!(
            e.to_string().ends_with("use a step of at least 2.4 nm"),
            "{e}"
        );
    }

    #[test]
    fn interpolation_is_exact_at_rows_and_linear_between() {
        let r = parse_response_csv(TABLE).unwrap();
        let ch = channels_from_response(&r, &[510.0, 515.0]).unwrap();
        // R: 1 at 510, 2.5 at 515 → weights 1/3.5, 2.5/3.5.
        assert!((ch[0].weights[0] - 1.0 / 3.5).abs() < 1e-15);
        assert!((ch[0].weights[1] - 2.5 / 3.5).abs() < 1e-15);
        // B is flat: equal weights.
        assert_eq!(ch[2].weights, vec![0.5, 0.5]);
        // The table's last wavelength is inside.
        assert!(channels_from_response(&r, &[520.0, 500.0]).is_ok());
    }

    #[test]
    fn out_of_table_and_all_zero_channels_are_refused() {
        let r = parse_response_csv(TABLE).unwrap();
        assert!(
            channels_from_response(&r, &[499.9])
                .unwrap_err()
                .to_string()
                .contains("499.9")
        );
        assert_eq!(
            channels_from_response(&r, &[520.1]),
            Err(SpectralError::SampleOutside {
                wavelength_nm: 520.1,
                lo_nm: 500.0,
                hi_nm: 520.0
            })
        );
        assert!(channels_from_response(&r, &[f64::NAN]).is_err());
        assert_eq!(
            channels_from_response(&r, &[]),
            Err(SpectralError::NoSamples)
        );
        // R is zero at 500 nm only.
        let e = channels_from_response(&r, &[500.0]).unwrap_err();
        assert_eq!(e, SpectralError::ZeroChannel { channel: "R" });
        assert!(e.to_string().contains("channel R"), "{e}");
    }
}
