//! The design's sampling warnings in the export report: a mask house (and the designer) reads
//! the LTR and the design's numbers with the same caveats the studio and `analyze` show.

use crate::IoError;
use udc_core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
use udc_core::design::Design;
use udc_core::mask::MaskError;
use udc_core::psf::warning::SamplingWarning;
use udc_core::{Progress, SimError};

/// The design's sampling warnings (a full analysis, as `udc-studio analyze` runs it), or why
/// they could not be had; a cancel stops the export.
pub(super) fn check(
    design: &Design,
    progress: &Progress,
) -> Result<(Vec<SamplingWarning>, Option<String>), IoError> {
    let options = AnalyzeOptions {
        quality: Quality::Full,
        expected_psf: false,
    };
    match analyze_with(design, &options, progress) {
        Ok(a) => Ok((a.warnings, None)),
        Err(SimError::Cancelled) => Err(MaskError::Cancelled.into()),
        // The mask is still what the design says; only the caveats are unknown.
        Err(e) => Ok((Vec::new(), Some(e.to_string()))),
    }
}

/// One line per sampling warning or note (`sampling warning: …`, `sampling note: …`), or one
/// saying there are none or why the sampling was not checked.
pub(super) fn lines(sampling: &[SamplingWarning], unchecked: Option<&str>) -> Vec<String> {
    if let Some(why) = unchecked {
        return vec![format!("sampling: not checked ({why})")];
    }
    if sampling.is_empty() {
        return vec!["sampling: no warnings".into()];
    }
    sampling
        .iter()
        .map(|w| format!("sampling {}: {}", w.severity.as_str(), w.message))
        .collect()
}
