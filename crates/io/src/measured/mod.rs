//! Measured PSFs on disk: raw frames in ([`read`]) and PSF sets out and back in: a `.npy`
//! array (`H×W` float64 for one channel, `H×W×C` for several, numpy's and the public UDC
//! datasets' layout) with a JSON sidecar of the same stem holding what an array cannot: the
//! camera's pixel pitch, the channels' names and wavelengths, simulated or measured, and what
//! the import did.

pub mod read;

use std::path::{Path, PathBuf};

use ndarray::Array3;
use serde::{Deserialize, Serialize};

use udc_core::measured::{PsfChannel, PsfSet, PsfSource};

use crate::IoError;
pub use read::{Encoding, FramePick, RawFrame, read_frame};

/// The sidecar's format name.
pub const SIDECAR_FORMAT: &str = "udc-studio-psf";

/// What a PSF set's sidecar holds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sidecar {
    /// Always [`SIDECAR_FORMAT`].
    pub format: String,
    /// The sidecar's version (1).
    pub version: u32,
    /// The camera's pixel pitch, µm.
    pub pixel_um: f64,
    /// Simulated or measured.
    pub source: PsfSource,
    /// The channels in the array's order.
    pub channels: Vec<SidecarChannel>,
    /// What the import did, one line (absent for a simulated set).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub import: Option<String>,
    /// The build that wrote it.
    #[serde(default)]
    pub tool_version: String,
}

/// One channel in a sidecar.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SidecarChannel {
    /// Its name.
    pub name: String,
    /// Its wavelength, when known, nm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wavelength_nm: Option<f64>,
}

/// The sidecar's path beside `array`: the same stem, `.json`.
pub fn sidecar_path(array: &Path) -> PathBuf {
    array.with_extension("json")
}

/// Writes `set` to `path` (`.npy`) and its sidecar beside it; returns both paths.
///
/// # Errors
/// A set that fails [`PsfSet::check`], a path not ending in `.npy`, an unwritable file.
pub fn write_psf_set(
    path: &Path,
    set: &PsfSet,
    import: Option<&str>,
) -> Result<Vec<PathBuf>, IoError> {
    use ndarray_npy::WriteNpyExt;
    if path.extension().and_then(|e| e.to_str()) != Some("npy") {
        return Err(IoError::Image {
            path: path.to_path_buf(),
            message:
                "a PSF set is written as .npy (with a .json sidecar): name it, for example, psf.npy"
                    .into(),
        });
    }
    set.check().map_err(|e| IoError::Image {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let n = set.side_px();
    let mut bytes = Vec::new();
    let written = if let [one] = set.channels.as_slice() {
        one.psf.write_npy(&mut bytes)
    } else {
        let c = set.channels.len();
        Array3::from_shape_fn((n, n, c), |(y, x, k)| set.channels[k].psf[[y, x]])
            .write_npy(&mut bytes)
    };
    written.map_err(|e| IoError::Image {
        path: path.to_path_buf(),
        message: format!("cannot encode the array: {e}"),
    })?;
    crate::safe_file::write_atomic(path, &bytes)?;
    let sidecar = Sidecar {
        format: SIDECAR_FORMAT.into(),
        version: 1,
        pixel_um: set.pixel_um,
        source: set.source,
        channels: set
            .channels
            .iter()
            .map(|c| SidecarChannel {
                name: c.name.clone(),
                wavelength_nm: c.wavelength_nm,
            })
            .collect(),
        import: import.map(str::to_owned),
        tool_version: crate::TOOL_VERSION.into(),
    };
    let json_path = sidecar_path(path);
    let text = serde_json::to_string_pretty(&sidecar).map_err(|e| IoError::Image {
        path: json_path.clone(),
        message: format!("cannot encode the sidecar: {e}"),
    })?;
    crate::safe_file::write_atomic(&json_path, text.as_bytes())?;
    Ok(vec![path.to_path_buf(), json_path])
}

/// What a PSF set read without a sidecar must be told.
#[derive(Debug, Clone, Default)]
pub struct SetDefaults {
    /// The camera's pixel pitch, µm (required without a sidecar; overrides it when given).
    pub pixel_um: Option<f64>,
    /// The wavelength of a single channel, nm.
    pub wavelength_nm: Option<f64>,
}

/// Reads a PSF set: a `.npy` (or any frame [`read_frame`] reads) with its sidecar when there is
/// one; each channel normalised to unit sum. A frame that is not square, or whose light is not
/// centred, belongs to `psf import` first (which says so).
///
/// # Errors
/// An unreadable file or sidecar, no pixel pitch, a set that fails [`PsfSet::check`].
pub fn read_psf_set(path: &Path, defaults: &SetDefaults) -> Result<PsfSet, IoError> {
    let bad = |message: String| IoError::Image {
        path: path.to_path_buf(),
        message,
    };
    let frame = read_frame(path, &FramePick::default())?;
    let side = sidecar_path(path);
    let sidecar: Option<Sidecar> = if side.is_file() && side != path {
        let text = crate::safe_file::read_bounded(&side, 1 << 20, "read the PSF's sidecar")?;
        let s: Sidecar = serde_json::from_slice(&text).map_err(|e| IoError::Image {
            path: side.clone(),
            message: format!("not a PSF sidecar: {e}"),
        })?;
        if s.format != SIDECAR_FORMAT {
            return Err(IoError::Image {
                path: side,
                message: format!("format is `{}`, not `{SIDECAR_FORMAT}`", s.format),
            });
        }
        Some(s)
    } else {
        None
    };
    let pixel_um = defaults
        .pixel_um
        .or(sidecar.as_ref().map(|s| s.pixel_um))
        .ok_or_else(|| {
            bad("the camera's pixel pitch is not known: give --pixel-um (no sidecar .json)".into())
        })?;
    let names: Vec<(String, Option<f64>)> = match &sidecar {
        Some(s) if s.channels.len() == frame.planes.len() => s
            .channels
            .iter()
            .map(|c| (c.name.clone(), c.wavelength_nm))
            .collect(),
        Some(s) => {
            return Err(bad(format!(
                "the sidecar names {} channels but the array has {}",
                s.channels.len(),
                frame.planes.len()
            )));
        }
        None if frame.planes.len() == 3 => ["R", "G", "B"]
            .into_iter()
            .map(|n| (n.to_owned(), None))
            .collect(),
        None => vec![(
            defaults
                .wavelength_nm
                .map_or("measured".to_owned(), |w| format!("{w} nm")),
            defaults.wavelength_nm,
        )],
    };
    let channels = frame
        .planes
        .into_iter()
        .zip(names)
        .map(|(psf, (name, wavelength_nm))| {
            let sum = psf.sum();
            PsfChannel {
                name,
                wavelength_nm,
                psf: if sum > 0.0 { psf / sum } else { psf },
            }
        })
        .collect();
    let set = PsfSet {
        channels,
        pixel_um,
        source: sidecar.map_or(PsfSource::Measured, |s| s.source),
    };
    set.check().map_err(|e| {
        bad(format!(
            "{e}; a raw frame becomes a PSF with `udc-studio psf import`"
        ))
    })?;
    Ok(set)
}
