//! What a real camera sees through the display beyond the ideal, on-axis PSF (thesis §3.7): the
//! PSF across the field ([`field`], and photos captured through it, [`field_capture`]), at a
//! finite depth ([`depth`], [`depth_capture`]), and highlights that clip against an
//! exposure-bracketed capture ([`saturation`]). Built on [`crate::analysis`] and
//! [`crate::restore`].

pub mod depth;
pub mod depth_capture;
pub mod field;
pub mod field_capture;
pub mod saturation;
