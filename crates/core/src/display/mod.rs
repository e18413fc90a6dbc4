//! The display in front of the camera: one pixel's opening ([`aperture`]), the panel it tiles
//! into ([`tiling`], [`opening_ops`]), how the panel looks to a viewer ([`appearance`],
//! [`emitters`]). What a camera sees through it beyond the ideal PSF is the `camera` module.

pub mod aperture;
pub mod appearance;
pub mod emitters;
pub mod figures;
pub mod opening_ops;
pub mod tiling;
