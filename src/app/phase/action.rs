//! What the phase workspace's panels ask for: every change of the design goes through this
//! queue and is carried out after the frame's UI ([`super::PhaseWorkspace::act`]), through the
//! undo history; so does every run, dialog and cancel a button asks for.

use super::{ChannelSet, HeightFormat, PhaseView, Quality};
use crate::core::phase::PhaseDesign;
use crate::core::restore::Denoise;

/// How the PSFs, the V matrix, the optimizer and the blur matrix are run: not part of the
/// design (no undo), kept while the design changes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhaseChoices {
    /// Preview only, or preview then the thesis sampling.
    pub quality: Quality,
    /// The colour channels.
    pub channels: ChannelSet,
    /// Lemma 1's comparison: one plate at the display, no second MLA.
    pub single_mask: bool,
    /// Incidence angle of the PSFs, in degrees.
    pub angle_deg: f64,
}

/// The light, channels, noise seed and denoiser of the capture view's runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CaptureChoices {
    /// Photons an open display aperture passes to a white pixel.
    pub photons: f64,
    /// The colour channels its operators are built for.
    pub channels: ChannelSet,
    /// The seed of the photon and read noise.
    pub seed: u64,
    /// The denoiser before the solver.
    pub denoise: Denoise,
}

/// A change or a request the panels queue.
#[derive(Debug, Clone)]
pub enum PhaseAction {
    /// A live edit from a control (a drag, a typed number): the design as edited. The history
    /// makes it one undo step once the pointer is up and no text field has focus.
    Live(Box<PhaseDesign>),
    /// A new design as one undo step (the thesis design).
    Set(Box<PhaseDesign>),
    /// The optimizer's allocation as the λ0 plan (one undo step), if it still fits.
    ApplyOptimized,
    /// Steps back one parameter change.
    Undo,
    /// Re-applies the change last undone.
    Redo,
    /// New run choices (quality, channels, optics, angle); the PSFs follow.
    Choose(PhaseChoices),
    /// The lenslet the plate profile and the per-lenslet editor show.
    SelectLenslet(usize),
    /// Show this picture in the centre.
    Show(PhaseView),
    /// Stop the running PSFs; the last ones stay.
    CancelPsfs,
    /// Compute the V matrix.
    ComputeV,
    /// Run the λ0 optimizer (V, then Algorithm 1).
    Optimize,
    /// Stop the V matrix and the optimizer.
    CancelOptimizer,
    /// The channel (0 R, 1 G, 2 B) the blur matrix is computed for.
    KernelChannel(usize),
    /// Compute the blur matrix of every direction.
    ComputeKernels,
    /// Ask where to save the blur matrix (a file dialog).
    AskKernelFile,
    /// Stop the blur matrix.
    CancelKernels,
    /// Ask for a sensor response CSV (a file dialog).
    AskResponse,
    /// Ask where to write the plate in this format (a file dialog).
    Export(HeightFormat),
    /// Ask for a photo to capture (a file dialog).
    AskCapturePhoto,
    /// Go back to the built-in photo.
    BuiltInCapturePhoto,
    /// New light, channels, seed or denoiser for the captures.
    Capture(CaptureChoices),
    /// Stop the running capture; the last pictures stay.
    CancelCapture,
    /// Run the setup comparison.
    RunCompare,
    /// Ask where to save the comparison (a file dialog).
    AskCompareFile,
    /// Stop the comparison.
    CancelCompare,
}
