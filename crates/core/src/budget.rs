//! What a job costs before it runs. Jobs whose working memory grows with an input's size
//! estimate their bytes from that size and are refused above the process's budget, with a
//! message that names what to change: before anything is allocated, so a refusal costs nothing.
//!
//! The budget is set once at start by the binary (`--max-memory`, else half the machine's
//! physical memory; see `io::system`); until then it is [`DEFAULT_MAX_MEMORY_BYTES`].

use std::sync::atomic::{AtomicU64, Ordering};

use crate::{SimError, ValueError};

/// The budget before the binary sets one: 4 GiB.
pub const DEFAULT_MAX_MEMORY_BYTES: u64 = 4 << 30;

/// Photo-sized samples (in the photo's type, `f32` or `f64`) a capture and restoration holds per
/// pixel at most when it hands its intermediate planes over as they are done
/// (`restore::simulate_with`): the photo, the denoised capture and the restoration, R, G and B
/// (the denoiser's two `f32` working planes take the place of the last two while it runs).
pub const RESTORE_SAMPLES_PER_PIXEL: u64 = 9;

/// The same when the capture and the denoised capture are kept too (`restore::simulate`).
pub const RESTORE_KEPT_SAMPLES_PER_PIXEL: u64 = 15;

/// What a restoration holds besides its planes: the row spectra of one strip of columns
/// (`restore::spectrum::STRIP_BYTES`), the kernel's row spectra, the denoiser's per-thread
/// caches and the program itself.
pub const RESTORE_FIXED_BYTES: u64 = 192 << 20;

/// Peak working bytes per photo pixel of a restoration by conjugate gradients, which keep the
/// kernel's and the iterate's whole padded spectra in `f64` (measured: 88 MB for a 512 × 512
/// photo, 40 MB for 256 × 256).
pub const RESTORE_CG_BYTES_PER_PIXEL: u64 = 256;

static MAX_MEMORY_BYTES: AtomicU64 = AtomicU64::new(DEFAULT_MAX_MEMORY_BYTES);

/// Sets the budget (bytes; at least 1 MiB).
pub fn set_max_memory_bytes(bytes: u64) {
    MAX_MEMORY_BYTES.store(bytes.max(1 << 20), Ordering::Relaxed);
}

/// The budget in bytes.
pub fn max_memory_bytes() -> u64 {
    MAX_MEMORY_BYTES.load(Ordering::Relaxed)
}

/// Refuses a job of `bytes` above the budget.
///
/// # Errors
/// [`SimError::TooLarge`]: "`job` needs about X GB of memory; the budget is Y GB: `change`,
/// or raise the budget with --max-memory".
pub fn check(job: &str, bytes: u64, change: &str) -> Result<(), SimError> {
    let budget = max_memory_bytes();
    if bytes <= budget {
        return Ok(());
    }
    Err(SimError::TooLarge(format!(
        "{job} needs about {} of memory; the budget is {}: {change}, or raise the budget with \
         --max-memory",
        format_bytes(bytes),
        format_bytes(budget)
    )))
}

/// Bytes for people: "1.5 GB", "300 MB".
pub fn format_bytes(bytes: u64) -> String {
    let b = bytes as f64;
    if b >= 1e9 {
        format!("{:.1} GB", b / 1e9)
    } else {
        format!("{:.0} MB", (b / 1e6).max(1.0))
    }
}

/// Parses a size: a number of bytes with an optional K, M, G or T suffix (powers of 1024;
/// `B`/`iB` accepted), e.g. `2G`, `512M`, `1.5GiB`.
///
/// # Errors
/// A message saying what a size looks like.
pub fn parse_size(text: &str) -> Result<u64, ValueError> {
    let t = text.trim();
    let upper = t.to_ascii_uppercase();
    let digits = upper.trim_end_matches(['B', 'I']);
    let (number, unit) = match digits.char_indices().last() {
        Some((i, c @ ('K' | 'M' | 'G' | 'T'))) => (&digits[..i], Some(c)),
        _ => (digits, None),
    };
    let scale: u64 = match unit {
        Some('K') => 1 << 10,
        Some('M') => 1 << 20,
        Some('G') => 1 << 30,
        Some('T') => 1 << 40,
        _ => 1,
    };
    let bad = || ValueError::Malformed {
        value: t.to_string(),
        expected: "a size (e.g. 2G, 512M or 1500000000)",
    };
    let v: f64 = number.trim().parse().map_err(|_| bad())?;
    if !(v.is_finite() && v > 0.0) {
        return Err(bad());
    }
    let bytes = v * scale as f64;
    if bytes > u64::MAX as f64 / 2.0 {
        return Err(ValueError::Unusable {
            value: t.to_string(),
            problem: "more memory than any machine has".into(),
        });
    }
    Ok(bytes as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_binary_suffixes() {
        assert_eq!(parse_size("2G"), Ok(2 << 30));
        assert_eq!(parse_size("512m"), Ok(512 << 20));
        assert_eq!(parse_size("1.5GiB"), Ok(3 << 29));
        assert_eq!(parse_size("1000"), Ok(1000));
        for bad in ["", "G", "-1G", "NaN", "abc", "1e400", "0"] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
    }
}
