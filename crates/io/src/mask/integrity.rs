//! The checksum an export writes beside a mask (`<file>.sha256`, and the `sha256` of
//! `<file>.manifest.json`), checked when the mask is read back: a file altered or damaged
//! after export is refused instead of read as another design.

use std::path::{Path, PathBuf};

use crate::IoError;
use crate::error::MaskImportError;
use crate::fab::{beside, sha256_hex};

/// The SHA-256 a sidecar of `path` states, and the sidecar; `None` without one.
fn stated(path: &Path) -> Result<Option<(String, PathBuf)>, IoError> {
    let err = |sidecar: &Path| IoError::MaskImport {
        path: path.to_path_buf(),
        error: MaskImportError::UnreadableChecksum {
            sidecar: sidecar.to_path_buf(),
        },
    };
    let is_hash = |h: &str| h.len() == 64 && h.bytes().all(|b| b.is_ascii_hexdigit());
    let sha = beside(path, ".sha256");
    if sha.is_file() {
        // `sha256sum` format: the hash, two spaces, the file name.
        let text = crate::safe_file::read_bounded(&sha, 4096, "read the checksum")?;
        let text = String::from_utf8_lossy(&text);
        let hash = text.split_whitespace().next().unwrap_or_default();
        return match is_hash(hash) {
            true => Ok(Some((hash.to_ascii_lowercase(), sha))),
            false => Err(err(&sha)),
        };
    }
    let manifest = beside(path, ".manifest.json");
    if manifest.is_file() {
        let text = crate::safe_file::read_bounded(&manifest, 1 << 20, "read the manifest")?;
        let value: serde_json::Value = serde_json::from_slice(&text).map_err(|_| err(&manifest))?;
        return match value.get("sha256").and_then(serde_json::Value::as_str) {
            Some(hash) if is_hash(hash) => Ok(Some((hash.to_ascii_lowercase(), manifest))),
            _ => Err(err(&manifest)),
        };
    }
    Ok(None)
}

/// Checks `path` against the checksum written beside it, when there is one.
///
/// # Errors
/// [`MaskImportError::ChecksumMismatch`] when the file's SHA-256 differs from the one stated,
/// [`MaskImportError::UnreadableChecksum`] when the sidecar states none; [`IoError::File`]
/// when a file cannot be read.
pub fn verify_checksum(path: &Path) -> Result<(), IoError> {
    let Some((expected, sidecar)) = stated(path)? else {
        return Ok(());
    };
    let bytes = crate::safe_file::read_bounded(path, super::MAX_MASK_BYTES, "read the mask")?;
    let found = sha256_hex(&bytes);
    if found == expected {
        return Ok(());
    }
    Err(IoError::MaskImport {
        path: path.to_path_buf(),
        error: MaskImportError::ChecksumMismatch {
            sidecar,
            expected,
            found,
        },
    })
}
