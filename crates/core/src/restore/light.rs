//! A capture conserves light (conventions.md §5): the PSF it blurs with must hold at least
//! [`MIN_CAPTURE_ENERGY_IN_WINDOW`] of the light that reaches the sensor plane. Every PSF is
//! normalised to sum 1 over its window, so light scattered beyond the window would otherwise be
//! dropped as if it never arrived; on a real sensor it lands as haze, and dropping it flatters the
//! fine pitches that scatter far (a P-OLED at 300 DPI keeps about half its light in a 294-pixel
//! window). The analysis module's `light` checks an analysis against it, in one line with the fix.

/// The least share of a channel's light that a capture's PSF window must hold. The thesis's
/// own recipe (150 DPI, 294-pixel window) holds 97.9 % in R.
pub const MIN_CAPTURE_ENERGY_IN_WINDOW: f64 = 0.97;

/// The least share, over `psfs`, of a PSF's light that lands within a frame of `frame`
/// `(rows, cols)` centred on its axis pixel (`[W/2, W/2]`): what a photo of that size can keep of
/// the light of one of its pixels. Light beyond the frame leaves a capture of the photo alone
/// (a linear convolution of a scene that ends at the photo's border), so a PSF that scatters
/// farther than the photo is wide blurs it less, whatever its window holds.
pub fn least_share_in_frame(psfs: &[&ndarray::Array2<f64>], frame: (usize, usize)) -> f64 {
    psfs.iter()
        .map(|p| {
            let (h, w) = p.dim();
            let rows = frame.0.min(h);
            let cols = frame.1.min(w);
            let (r0, c0) = (
                (h / 2).saturating_sub(rows / 2),
                (w / 2).saturating_sub(cols / 2),
            );
            let total = p.sum();
            let inside: f64 = p
                .rows()
                .into_iter()
                .skip(r0)
                .take(rows)
                .map(|row| row.iter().skip(c0).take(cols).sum::<f64>())
                .sum();
            if total > 0.0 {
                inside / total
            } else {
                f64::NAN
            }
        })
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_share_in_a_frame_counts_the_centred_box() {
        // A PSF with half its light on the axis pixel and half 3 pixels to the right.
        let mut p = ndarray::Array2::<f64>::zeros((9, 9));
        p[[4, 4]] = 0.5;
        p[[4, 7]] = 0.5;
        assert_eq!(least_share_in_frame(&[&p], (9, 9)), 1.0);
        assert_eq!(least_share_in_frame(&[&p], (5, 5)), 0.5);
        assert_eq!(least_share_in_frame(&[&p], (1, 8)), 1.0);
        assert_eq!(least_share_in_frame(&[&p], (1, 1)), 0.5);
        let mut q = p.clone();
        q[[4, 7]] = 0.0;
        q[[4, 4]] = 1.0;
        assert_eq!(least_share_in_frame(&[&q, &p], (5, 5)), 0.5);
    }
}
