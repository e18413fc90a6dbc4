//! The numbers a study records: the analysis's (AUC, LTR, `L_inv`), the restoration's (PSNR,
//! SSIM) and the phase masks' (per channel: invertibility, light against the bare T-OLED,
//! peak; the light transmittance), each a column of its job's JSON object.

use crate::design::Design;
use crate::sweep::SweepJob;
use crate::sweep::one_axis::SweepMetric;

/// The colour channel a phase-mask study plots per-channel numbers of (the folding
/// wavelength's: the thesis's fixed 530 nm).
pub const PHASE_PLOT_CHANNEL: &str = "G";

/// One number a study records.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum StudyMetric {
    /// The display design's analysis (mean AUC, a channel's AUC, LTR, `L_inv`).
    Analysis(SweepMetric),
    /// PSNR of the restoration against the photo, dB.
    PsnrDb,
    /// SSIM of the restoration against the photo.
    Ssim,
    /// Invertibility of the phase masks' PSF, per channel.
    PhaseInvertibility,
    /// Light through the phase masks over the bare T-OLED's, per channel.
    PhaseLightVsToled,
    /// Peak of the phase masks' PSF, per channel.
    PhasePeak,
    /// Light transmittance of the phase masks with the polariser.
    PhaseLtr,
}

impl StudyMetric {
    /// The metrics a display study offers for `design` (the restoration's count when the
    /// study restores).
    pub fn display(design: &Design) -> Vec<StudyMetric> {
        let mut v: Vec<StudyMetric> = SweepMetric::all_for(design)
            .into_iter()
            .map(StudyMetric::Analysis)
            .collect();
        v.extend([StudyMetric::PsnrDb, StudyMetric::Ssim]);
        v
    }

    /// The metrics a phase-mask study offers.
    pub const PHASE: [StudyMetric; 4] = [
        StudyMetric::PhaseInvertibility,
        StudyMetric::PhaseLightVsToled,
        StudyMetric::PhasePeak,
        StudyMetric::PhaseLtr,
    ];

    /// Its name on screen, with the unit.
    pub fn label(self, design: &Design) -> String {
        match self {
            StudyMetric::Analysis(m) => m.label(design),
            StudyMetric::PsnrDb => "PSNR (dB)".into(),
            StudyMetric::Ssim => "SSIM".into(),
            StudyMetric::PhaseInvertibility => "invertibility per channel".into(),
            StudyMetric::PhaseLightVsToled => "light vs bare T-OLED per channel".into(),
            StudyMetric::PhasePeak => "PSF peak per channel".into(),
            StudyMetric::PhaseLtr => "LTR with polariser".into(),
        }
    }

    /// Whether `job` reports it: the restoration's numbers only a restore job, the analysis's
    /// an analysis (a restore job reports the mean AUC and LTR too), the phase masks' only
    /// `phase psf`.
    pub fn recorded_by(self, job: SweepJob) -> bool {
        match (self, job) {
            (StudyMetric::Analysis(_), SweepJob::Analyze) => true,
            (StudyMetric::Analysis(m), SweepJob::Restore) => {
                matches!(m, SweepMetric::AucMean | SweepMetric::Ltr)
            }
            (StudyMetric::PsnrDb | StudyMetric::Ssim, SweepJob::Restore) => true,
            (
                StudyMetric::PhaseInvertibility
                | StudyMetric::PhaseLightVsToled
                | StudyMetric::PhasePeak
                | StudyMetric::PhaseLtr,
                SweepJob::PhasePsf,
            ) => true,
            _ => false,
        }
    }

    /// Its column among the job's metrics (the path into its JSON object; `*` for every
    /// channel).
    pub fn column(self, design: &Design) -> String {
        match self {
            StudyMetric::Analysis(m) => m.column(design),
            // A study restores at one light level per point: the first run is the point's.
            StudyMetric::PsnrDb => "runs.0.psnr_db".into(),
            StudyMetric::Ssim => "runs.0.ssim".into(),
            StudyMetric::PhaseInvertibility => "channels.*.invertibility".into(),
            StudyMetric::PhaseLightVsToled => "channels.*.energy_vs_toled".into(),
            StudyMetric::PhasePeak => "channels.*.peak".into(),
            StudyMetric::PhaseLtr => "ltr_with_polariser".into(),
        }
    }

    /// The one column a plot of it draws: a per-channel number's
    /// [`PHASE_PLOT_CHANNEL`].
    pub fn plot_column(self, design: &Design) -> String {
        self.column(design).replace('*', PHASE_PLOT_CHANNEL)
    }
}
