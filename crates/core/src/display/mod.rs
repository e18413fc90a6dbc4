//! The display in front of the camera: one pixel's opening ([`aperture`]), the panel it tiles
//! into ([`tiling`], [`opening_ops`]), how the panel looks to a viewer ([`appearance`],
//! [`emitters`]), and what a real camera sees beyond the ideal PSF (thesis §3.7): the PSF across
//! the field ([`field`], [`field_capture`]), at finite depth ([`depth`], [`depth_capture`]) and
//! with clipping and exposure bracketing ([`saturation`]).

pub mod aperture;
pub mod appearance;
pub mod depth;
pub mod depth_capture;
pub mod emitters;
pub mod field;
pub mod field_capture;
pub mod opening_ops;
pub mod saturation;
pub mod tiling;
