//! The integration tests, linked into one binary: each file here is a module, so CI links the
//! heavy GUI stack once instead of once per file.

mod common;

mod advice;
mod architecture;
mod cli;
mod cli_optimize;
mod cli_phase;
mod cli_restore;
mod cli_sensor;
mod corpus;
mod design_file;
mod drop;
mod expected_psf;
mod io_files;
mod layouts;
mod mask_dialog;
mod mask_export;
mod mask_geometry;
mod opening_ops;
mod optimize;
mod optimize_panel;
mod phase;
mod phase_capture;
mod phase_export;
mod phase_imaging;
mod phase_panel;
mod physics;
mod restore;
mod restore_view;
mod safe_file;
mod screenshots;
mod sensor;
mod sensor_colour;
mod sensor_gain;
mod sensor_hdr;
mod sensor_noise;
mod sensor_panel;
mod sensor_pitch;
mod sensor_saturation;
mod sensor_study;
mod sensor_table54;
mod studio;
mod theory;
mod thesis;
mod views;
