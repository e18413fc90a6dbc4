//! The hash a sweep row records for the design it computed, so that the studio can tell that a
//! design it opens for a row is the one the row was computed on. (A design is chosen, from a
//! file or a preset and overrides, by the job layer's `DesignSelection`.)

use udc_core::design::Design;

/// The hash a sweep row records for its design (`design_hash`): of the design's file form.
pub fn design_hash(design: &Design) -> String {
    udc_core::sweep::hash::short_hash(serde_json::to_string(design).unwrap_or_default().as_bytes())
}
