//! The memory a decode will hold, checked against the job budget (`udc_core::budget`) from the
//! header's size, before any pixel is decoded: under a tight cap (`prlimit --as`, a batch
//! job's limit) a reader refuses in one line instead of failing an allocation halfway.
//!
//! Each reader states its own peak in bytes per pixel (the decoder's buffer in the file's
//! sample type, the planes it builds, the copy the two overlap with) and the bytes it already
//! holds (the file read into memory).

use udc_core::SimError;

/// Refuses to decode a `width × height` image whose peak, `bytes_per_pixel` per pixel beside
/// `held_bytes` already held, is over the budget. `what` names the image in the message
/// ("the HDR image scene.hdr").
///
/// # Errors
/// [`SimError::TooLarge`]: "decoding the 4096×4096 HDR image … needs about 671 MB of memory;
/// the budget is 400 MB: use a smaller image, or raise the budget with --max-memory".
pub fn check(
    what: &str,
    width: u64,
    height: u64,
    bytes_per_pixel: u64,
    held_bytes: u64,
) -> Result<(), SimError> {
    let bytes = width
        .saturating_mul(height)
        .saturating_mul(bytes_per_pixel)
        .saturating_add(held_bytes);
    udc_core::budget::check(
        &format!("decoding the {width}×{height} {what}"),
        bytes,
        "use a smaller image",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_peak_counts_the_pixels_and_what_is_held() {
        // The budget is process-wide; other tests in this binary leave it at its default.
        let budget = udc_core::budget::max_memory_bytes();
        let side = 1u64 << 12;
        let per_pixel = budget / (side * side);
        assert!(check("image a.png", side, side, per_pixel, 0).is_ok());
        let e = check("image a.png", side, side, per_pixel, budget).unwrap_err();
        assert!(matches!(e, SimError::TooLarge(_)));
        let text = e.to_string();
        assert!(
            text.contains("decoding the 4096×4096 image a.png"),
            "{text}"
        );
        assert!(text.contains("the budget is"), "{text}");
        // Sizes that overflow are refused, not wrapped.
        assert!(check("image", u64::MAX, u64::MAX, 36, 0).is_err());
    }
}
