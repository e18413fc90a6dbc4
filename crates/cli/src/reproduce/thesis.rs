//! The thesis's published numbers and claims, in one place, each with the table or figure it
//! comes from and, where the markdown copy of the thesis names it, the page ("PDF p. N": the
//! page images `_page_N_…` around it).
//! Reports quote these beside our numbers; nothing else in the crate copies them.

/// One row of a thesis table: PSNR in dB and SSIM, and the LTR in per cent where printed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThesisRow {
    /// The row's name in the thesis.
    pub setup: &'static str,
    /// Light transmittance ratio in per cent, where the table prints one.
    pub ltr_percent: Option<f64>,
    /// PSNR, dB; `None` where the thesis prints none.
    pub psnr_db: Option<f64>,
    /// SSIM; `None` where the thesis prints none.
    pub ssim: Option<f64>,
}

const fn row(setup: &'static str, ltr: Option<f64>, psnr: f64, ssim: f64) -> ThesisRow {
    ThesisRow {
        setup,
        ltr_percent: ltr,
        psnr_db: Some(psnr),
        ssim: Some(ssim),
    }
}

/// Where Table 4.1 comes from.
pub const TABLE_4_1_SOURCE: &str = "thesis §4.5, Table 4.1 (PDF p. 82): mean PSNR / SSIM over \
    30 test photos and the light levels 250 … 10 000 photons, 600 DPI";

/// Table 4.1: comparisons with other OLED displays (600 DPI; ZTE Axon at its own low DPI).
pub const TABLE_4_1: [ThesisRow; 5] = [
    row("TOLED", Some(23.8), 22.42, 0.59),
    row("POLED", Some(8.3), 26.22, 0.67),
    row("Ours", Some(47.6), 28.01, 0.75),
    row("Yang et al.", Some(22.6), 32.93, 0.88),
    row("ZTE Axon", Some(75.0), 38.24, 0.96),
];

/// Table 4.1's margin of the double MLA over the bare T-OLED, dB (28.01 − 22.42).
pub const TABLE_4_1_MARGIN_DB: f64 = 28.01 - 22.42;

/// Where Table 4.2 comes from.
pub const TABLE_4_2_SOURCE: &str = "thesis §4.5, Table 4.2 (PDF p. 84): T = 1, about 1600 \
    photons, 30 test photos";

/// Table 4.2: the order of the folding heights d_l (λ0) at T = 1, 1600 photons.
pub const TABLE_4_2: [ThesisRow; 4] = [
    row("uniform, ordered", None, 26.69, 0.7106),
    row("uniform, shuffled", None, 26.51, 0.7187),
    row("optimized, ordered", None, 27.44, 0.7368),
    row("optimized, shuffled", None, 27.18, 0.7396),
];

/// Table 4.2's ΔPSNR of shuffling, per cent of the ordered PSNR (uniform, optimized).
pub const TABLE_4_2_DELTA_PSNR_PERCENT: [f64; 2] = [-0.68, -0.96];
/// Table 4.2's ΔSSIM of shuffling, per cent (uniform, optimized).
pub const TABLE_4_2_DELTA_SSIM_PERCENT: [f64; 2] = [1.13, 0.38];
/// The bound the thesis's text puts on the cost of shuffling ("negligible"; both ΔPSNR < 1 %).
pub const TABLE_4_2_NEGLIGIBLE_PERCENT: f64 = 1.0;

/// Where Table 5.4 comes from.
pub const TABLE_5_4_SOURCE: &str = "thesis §5.7, Table 5.4 (PDF p. 109–110): worst-ROI SSIM, average \
    of 10 Fairchild HDR scenes";

/// Table 5.4's average worst-ROI SSIM of the four strategies (const gain/no bin, vary gain/no
/// bin, const gain/vary bin, vary gain/vary bin); the LPIPS column is not computed here.
pub const TABLE_5_4_AVERAGE_SSIM: [(&str, f64); 4] = [
    ("const-gain/no-bin", 0.18),
    ("vary-gain/no-bin", 0.30),
    ("const-gain/vary-bin", 0.28),
    ("vary-gain/vary-bin", 0.39),
];

/// Where Table 5.1 comes from.
pub const TABLE_5_1_SOURCE: &str = "thesis §5.5.2, Table 5.1 (PDF p. 105): total noise variance \
    of the per-pixel estimate for each binning mode (formulas, no numbers)";

/// Table 5.1's formulas as printed, by mode.
pub const TABLE_5_1_FORMULAS: [(&str, &str); 4] = [
    ("none", "l* + σ_pre² + σ_post²/g²"),
    ("additive", "l*/N + σ_pre²/N + σ_post²/(N² ĝ²)"),
    ("average", "l*/N + σ_pre²/N + σ_post²/g²"),
    ("digital", "l*/N + σ_pre²/N + σ_post²/(N g²)"),
];

/// Fig. 3.8's claims (§3.5; the figure only plots; the markdown copy numbers no pages in
/// chapter 3).
pub const FIG_3_8_CLAIM_RANDOM: &str = "introducing random tiling provides improvements in both \
    metrics (T-OLED and the optimized openings)";
/// The optimized random layout's margin over the T-OLED that §3.5 states, dB and SSIM.
pub const FIG_3_8_BEST_MARGIN: (f64, f64) = (8.0, 0.11);
/// The margin the reproduction must reach to pass (the bound, below the thesis's 8 dB:
/// no BM3D tuning and another photo set).
pub const FIG_3_8_REQUIRED_MARGIN_DB: f64 = 6.0;

/// Fig. 3.9's claims (§3.5; SNR 32 dB, 80–300 DPI; the figure only plots).
pub const FIG_3_9_CLAIMS: [&str; 3] = [
    "the recovered image quality decreases as pixel density increases",
    "the optimized patterns outperform T-OLED and P-OLED under all pixel densities",
    "the improvement on P-OLED is not as significant as on T-OLED",
];

/// Fig. 4.10's claims (§4.5, PDF p. 83; 1600 photons; the figure only plots).
pub const FIG_4_10_CLAIMS: [&str; 3] = [
    "at 5 µm (T = 5), optimized phase masks outperform TOLED at all four pixel densities",
    "at 1 µm (T = 1), ours outperform TOLED with pixel densities larger than 300 DPI",
    "quantized phase masks (200 nm steps) perform similarly to ones before quantization",
];

/// Fig. 4.14's claims (§4.5, PDF p. 86; the figure only plots).
pub const FIG_4_14_CLAIMS: [&str; 3] = [
    "the proposed setup outperforms TOLED at all light levels",
    "at 250 photons, POLED is worse than ours by around 10 dB in PSNR",
    "the performance of POLED increases fast as the light level increases",
];
/// The gap at 250 photons that §4.5 states, dB ("around 10 dB").
pub const FIG_4_14_POLED_GAP_250_DB: f64 = 10.0;

/// The sentence every report carries about the photos.
pub const PHOTO_SET_NOTE: &str = "The thesis averaged 30 photos of a test set we do not have \
    (Zhou et al. 2020's UDC validation set, §3.5 and §4.5); our numbers average the photos \
    listed below, so absolute values are not expected to match, the orderings and margins are.";
