//! The physics, thesis and format-free tests of the core, in their own binary: `cargo test -p
//! udc-core` runs them without building the studio. The test data (presets, reference patterns,
//! photos) are read through `udc-io`, a dev-dependency only: the library itself reads no files.

mod common;

mod emitters;
mod expected_psf;
mod fft_plans;
mod mask_geometry;
mod measured;
mod measured_fit;
mod optimize;
mod phase;
mod phase_period;
mod physics;
mod preview;
mod psf_route;
mod restore;
mod sensor;
mod sensor_gain;
mod sensor_hdr;
mod sensor_noise;
mod sensor_pitch;
mod sensor_saturation;
mod sensor_table54;
mod theory;
mod thesis;
