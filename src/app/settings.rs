//! View settings and recent files (persisted, never undone) and where the studio keeps them.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::io::IoError;
use crate::io::safe_file::write_atomic;

const MAX_RECENT: usize = 8;

/// Where the studio keeps its own files (autosave, settings). Tests point it at a temp dir.
#[derive(Debug, Clone)]
pub struct AppDirs {
    /// The folder of the settings, the autosave and the phase design; `None`: nothing is kept.
    pub data_dir: Option<PathBuf>,
}

impl AppDirs {
    /// The platform data directory (e.g. `~/.local/share/udc-studio`).
    pub fn platform() -> Self {
        AppDirs {
            data_dir: directories::ProjectDirs::from("org", "udc-studio", "udc-studio")
                .map(|d| d.data_dir().to_path_buf()),
        }
    }

    /// No persistence at all.
    pub fn none() -> Self {
        AppDirs { data_dir: None }
    }

    /// Keeps everything in `dir` (tests and portable setups).
    pub fn at(dir: &Path) -> Self {
        AppDirs {
            data_dir: Some(dir.to_path_buf()),
        }
    }

    /// The display workspace's autosave file, `autosave.json` in the data directory.
    pub fn autosave_path(&self) -> Option<PathBuf> {
        self.data_dir.as_ref().map(|d| d.join("autosave.json"))
    }

    fn settings_path(&self) -> Option<PathBuf> {
        self.data_dir.as_ref().map(|d| d.join("settings.json"))
    }
}

/// The persisted view settings, kept in `settings.json` in the data directory.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Settings {
    /// Recently opened or saved design files, newest first (at most 8), for File > Open recent.
    pub recent: Vec<PathBuf>,
    /// Dark theme (the default) rather than light.
    pub dark: bool,
    /// Teaching overlays and "What am I seeing?" hints shown (the default).
    pub overlays: bool,
    /// Design-rule rings on the opening editor (off by default: View > Design rules on the
    /// editor turns them on).
    pub design_rules: bool,
    /// The sweep results folder last opened, for File > Reopen in the Sweep workspace.
    pub last_sweep: Option<PathBuf>,
    /// Presentation mode (View > Presentation): for a projector.
    #[serde(default)]
    pub presentation: bool,
    /// Where the display's PSFs are computed (View > Compute PSFs on): the CPU (the default)
    /// or the window's GPU.
    #[serde(default)]
    pub backend: crate::core::psf::route::Backend,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            recent: Vec::new(),
            dark: true,
            overlays: true,
            design_rules: false,
            last_sweep: None,
            presentation: false,
            backend: crate::core::psf::route::Backend::Cpu,
        }
    }
}

impl Settings {
    /// Loads settings; anything unreadable falls back to defaults (settings are not precious).
    pub fn load(dirs: &AppDirs) -> Self {
        dirs.settings_path()
            .and_then(|p| {
                crate::io::safe_file::read_text_bounded(&p, 1 << 20, "read the settings").ok()
            })
            .and_then(|t| serde_json::from_str(&t).ok())
            .unwrap_or_default()
    }

    /// Saves settings; failures are returned so the UI can mention them.
    ///
    /// # Errors
    /// When the data directory cannot be written.
    pub fn save(&self, dirs: &AppDirs) -> Result<(), IoError> {
        let Some(path) = dirs.settings_path() else {
            return Ok(());
        };
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|cause| IoError::File {
                action: "create the settings folder",
                path: dir.to_path_buf(),
                cause,
            })?;
        }
        let text = serde_json::to_string_pretty(self).unwrap_or_default();
        write_atomic(&path, text.as_bytes())
    }

    /// Puts `path` first in the recent files, removing its older entry and the oldest beyond 8.
    pub fn add_recent(&mut self, path: &Path) {
        self.recent.retain(|p| p != path);
        self.recent.insert(0, path.to_path_buf());
        self.recent.truncate(MAX_RECENT);
    }
}
