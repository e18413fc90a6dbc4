//! Native file dialogs, always on a helper thread: a modal dialog on the UI thread would freeze
//! rendering (and hang headless tests). The app polls for the answer each frame.

use std::path::PathBuf;
use std::sync::mpsc::{Receiver, TryRecvError, channel};

/// What the chosen path is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Purpose {
    Open,
    SaveAs,
    ImportPattern,
    Spectral,
    /// A photo for the Restore view (the view polls its own dialog).
    Photo,
    /// An HDR scene for the sensor previewer (it polls its own dialog).
    Hdr,
    Export(super::commands::ExportKind),
    Mask(crate::io::mask::MaskFormat),
}

/// A dialog in flight.
pub struct PendingDialog {
    pub purpose: Purpose,
    rx: Receiver<Option<PathBuf>>,
}

impl PendingDialog {
    /// Opens a native dialog on a helper thread.
    pub fn spawn(purpose: Purpose, start_dir: Option<PathBuf>, file_name: Option<String>) -> Self {
        let (tx, rx) = channel();
        let spawned = std::thread::Builder::new()
            .name("file-dialog".into())
            .spawn(move || {
                let mut d = rfd::FileDialog::new();
                if let Some(dir) = start_dir {
                    d = d.set_directory(dir);
                }
                let path = match purpose {
                    Purpose::Open => d
                        .add_filter("UDC design", &["json"])
                        .set_title("Open design")
                        .pick_file(),
                    Purpose::ImportPattern => d
                        .add_filter(
                            "Openings (images, GDSII, DXF)",
                            &[
                                "png", "bmp", "tif", "tiff", "jpg", "jpeg", "gds", "gds2", "dxf",
                            ],
                        )
                        .set_title("Import opening: an image, or the axis pixel of a mask")
                        .pick_file(),
                    Purpose::Spectral => d
                        .add_filter("Spectral response CSV", &["csv"])
                        .set_title("Load spectral response (wavelength_nm, r, g, b)")
                        .pick_file(),
                    Purpose::Photo => d
                        .add_filter("Photos", &["png", "jpg", "jpeg"])
                        .set_title("Open a photo to capture through the display")
                        .pick_file(),
                    Purpose::Hdr => d
                        .add_filter("HDR scenes", &["hdr", "exr"])
                        .set_title("Open an HDR scene (Radiance .hdr or OpenEXR .exr)")
                        .pick_file(),
                    Purpose::SaveAs => d
                        .add_filter("UDC design", &["json"])
                        .set_file_name(file_name.unwrap_or_else(|| "design.json".into()))
                        .set_title("Save design as")
                        .save_file(),
                    Purpose::Export(kind) => d
                        .add_filter(kind.label().trim_end_matches('…'), &[kind.extension()])
                        .set_file_name(
                            file_name.unwrap_or_else(|| format!("export.{}", kind.extension())),
                        )
                        .set_title("Export")
                        .save_file(),
                    Purpose::Mask(format) => d
                        .add_filter(format.label(), &[format.extension()])
                        .set_file_name(
                            file_name.unwrap_or_else(|| format!("mask.{}", format.extension())),
                        )
                        .set_title("Export mask")
                        .save_file(),
                };
                let _ = tx.send(path);
            });
        if spawned.is_err() {
            // No thread, no dialog: the receiver reports a cancelled dialog.
            let (tx2, rx2) = channel();
            let _ = tx2.send(None);
            return PendingDialog { purpose, rx: rx2 };
        }
        PendingDialog { purpose, rx }
    }

    /// `Some(answer)` once the user closed the dialog (`None` inside = cancelled).
    pub fn poll(&self) -> Option<Option<PathBuf>> {
        match self.rx.try_recv() {
            Ok(p) => Some(p),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(None),
        }
    }
}
