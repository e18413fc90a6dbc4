//! Files in and out, safely. Every reader and writer of the studio goes through here.
//!
//! - **Inputs** must be regular files and are read under a byte cap that does not trust the
//!   file's metadata (`/dev/zero` reports 0 bytes and never ends; opening a FIFO blocks until a
//!   writer comes): the type is checked before opening and the read stops one byte past the cap.
//! - **Outputs** are written to a uniquely named temp file beside the target (`.NAME.XXXXXX.part`,
//!   so two exports to one target never share it) and renamed into place. The temp file is
//!   removed on every error path (on drop) and on Ctrl-C / SIGTERM, through
//!   [`remove_temp_files_on_signal`], which the binary installs at start.

use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use super::IoError;

/// Temp files in flight, removed by the signal handler.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// `dir/NAME.EXT` → `dir/NAME{suffix}.EXT` (no extension: `dir/NAME{suffix}`).
pub fn with_stem_suffix(path: &Path, suffix: &str) -> PathBuf {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let ext = path
        .extension()
        .map(|e| format!(".{}", e.to_string_lossy()))
        .unwrap_or_default();
    path.with_file_name(format!("{stem}{suffix}{ext}"))
}

/// Moves an unreadable file aside instead of losing it: `NAME.json` becomes
/// `NAME.unreadable.json`, or `NAME.unreadable-2.json`, `-3`, … when earlier copies are there
/// (an earlier copy is never overwritten). Returns the new path.
///
/// # Errors
/// [`IoError::File`] when the file cannot be moved.
pub fn keep_aside(path: &Path) -> Result<PathBuf, IoError> {
    for k in 1..10_000u32 {
        let suffix = if k == 1 {
            String::new()
        } else {
            format!("-{k}")
        };
        let aside = with_stem_suffix(path, &format!(".unreadable{suffix}"));
        // A hard link fails when the name is taken, so two studios never pick the same copy.
        match std::fs::hard_link(path, &aside) {
            Ok(()) => {
                std::fs::remove_file(path)
                    .map_err(|e| IoError::file("move the unreadable file aside", path, e))?;
                return Ok(aside);
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(_) if !aside.exists() => {
                // File systems without hard links: a plain rename to a free name.
                std::fs::rename(path, &aside)
                    .map_err(|e| IoError::file("move the unreadable file aside", path, e))?;
                return Ok(aside);
            }
            Err(_) => {}
        }
    }
    Err(IoError::file(
        "move the unreadable file aside",
        path,
        std::io::Error::other("too many earlier copies"),
    ))
}

/// Refuses an output `out` that is the same file as one of `inputs` (after following links and
/// `..`), so a command never overwrites what it read. An output that does not exist yet is never
/// an input.
///
/// # Errors
/// [`IoError::OutputIsInput`].
pub fn check_not_an_input(out: &Path, inputs: &[&Path]) -> Result<(), IoError> {
    let Ok(target) = std::fs::canonicalize(out) else {
        return Ok(());
    };
    if inputs
        .iter()
        .filter_map(|p| std::fs::canonicalize(p).ok())
        .any(|p| p == target)
    {
        return Err(IoError::OutputIsInput {
            path: out.to_path_buf(),
        });
    }
    Ok(())
}

/// `path` names a regular file (symlinks followed); anything else (a directory, a FIFO, a
/// device) is refused before it is opened.
///
/// Returns its length in bytes as the file system states it (a hint, not a bound).
///
/// # Errors
/// [`IoError::File`] when it does not exist or cannot be looked at, [`IoError::NotAFile`] when
/// it is not a regular file.
pub fn check_regular(path: &Path, what: &'static str) -> Result<u64, IoError> {
    let meta = std::fs::metadata(path).map_err(|e| IoError::file(what, path, e))?;
    if !meta.is_file() {
        let kind = if meta.is_dir() {
            "a directory"
        } else {
            "not a regular file (a device, FIFO or socket)"
        };
        return Err(IoError::NotAFile {
            path: path.to_path_buf(),
            kind,
        });
    }
    Ok(meta.len())
}

/// The bytes of a regular file of at most `cap` bytes.
///
/// # Errors
/// As [`check_regular`]; [`IoError::TooLarge`] past `cap` (whatever the metadata said).
pub fn read_bounded(path: &Path, cap: u64, what: &'static str) -> Result<Vec<u8>, IoError> {
    let len = check_regular(path, what)?;
    let too_large = || IoError::TooLarge {
        path: path.to_path_buf(),
        cap,
    };
    if len > cap {
        return Err(too_large());
    }
    // The whole file is held: refused in one line where the memory budget cannot.
    udc_core::budget::check(
        &format!("reading {} into memory", path.display()),
        len,
        "use a smaller file",
    )?;
    let file = File::open(path).map_err(|e| IoError::file(what, path, e))?;
    let mut bytes = Vec::with_capacity(usize::try_from(len).unwrap_or(0));
    file.take(cap.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| IoError::file(what, path, e))?;
    if bytes.len() as u64 > cap {
        return Err(too_large());
    }
    Ok(bytes)
}

/// The UTF-8 text of a regular file of at most `cap` bytes; a leading byte-order mark is
/// dropped (every text format of the studio accepts one).
///
/// # Errors
/// As [`read_bounded`]; [`IoError::NotText`] for bytes that are not UTF-8.
pub fn read_text_bounded(path: &Path, cap: u64, what: &'static str) -> Result<String, IoError> {
    let bytes = read_bounded(path, cap, what)?;
    let text = String::from_utf8(bytes).map_err(|e| IoError::NotText {
        path: path.to_path_buf(),
        offset: e.utf8_error().valid_up_to(),
    })?;
    Ok(match text.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_string(),
        None => text,
    })
}

/// A temp file beside its target: write to [`TempFile::path`], then [`TempFile::persist`].
/// Dropped without persisting (an error, a panic, a cancel), it is removed.
#[derive(Debug)]
pub struct TempFile {
    temp: Option<tempfile::TempPath>,
    target: PathBuf,
}

/// The operating system's error inside `e`, without the path a wrapper (tempfile: `… at path
/// "…"`) appended to its message: [`IoError::File`] names the path itself, once. tempfile's
/// wrapper is private and hides the inner error from `source()`, so its message is cut.
fn os_cause(e: std::io::Error) -> std::io::Error {
    if e.raw_os_error().is_some() {
        return e;
    }
    let text = e.to_string();
    match text.rfind(" at path ") {
        Some(i) => std::io::Error::new(e.kind(), text[..i].to_string()),
        None => e,
    }
}

/// Opens a temp file [`TempFile::beside`] reserved, for writing, without creating it: once
/// the signal handler has removed it (Ctrl-C), a writer that comes later fails instead of
/// leaving a new `.part` file behind.
///
/// # Errors
/// The file is gone or cannot be written.
pub fn open_reserved(path: &Path) -> std::io::Result<std::fs::File> {
    std::fs::OpenOptions::new()
        .write(true)
        .truncate(true)
        .open(path)
}

impl TempFile {
    /// Reserves a unique temp file in `target`'s directory.
    ///
    /// # Errors
    /// [`IoError::File`] when the directory cannot take a file.
    pub fn beside(target: &Path) -> Result<Self, IoError> {
        let dir = target
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let name = target
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let prefix = format!(".{name}.");
        let mut builder = tempfile::Builder::new();
        builder.prefix(&prefix).suffix(".part");
        // tempfile makes private (0600) files; a saved file is the user's document and gets
        // the usual mode (0666 less the umask), like any file an editor saves.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            builder.permissions(std::fs::Permissions::from_mode(0o666));
        }
        let temp = builder
            .tempfile_in(dir)
            // The error names the target once: tempfile's own error appends the temp file's
            // path, which the user never asked for and which repeated the directory.
            .map_err(|e| IoError::file("create the file", target, os_cause(e)))?
            .into_temp_path();
        if let Ok(mut live) = LIVE.lock() {
            live.push(temp.to_path_buf());
        }
        Ok(TempFile {
            temp: Some(temp),
            target: target.to_path_buf(),
        })
    }

    /// Where to write (the file exists, empty).
    pub fn path(&self) -> &Path {
        self.temp.as_deref().unwrap_or(&self.target)
    }

    /// Renames the temp file to the target, replacing it.
    ///
    /// # Errors
    /// [`IoError::File`] naming the target (the temp file is removed).
    pub fn persist(mut self) -> Result<(), IoError> {
        let Some(temp) = self.temp.take() else {
            return Ok(());
        };
        let at = temp.to_path_buf();
        let result = temp
            .persist(&self.target)
            .map_err(|e| IoError::file("replace", &self.target, e.error));
        forget(&at);
        result
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if let Some(temp) = self.temp.take() {
            let at = temp.to_path_buf();
            // TempPath's own drop removes the file.
            drop(temp);
            forget(&at);
        }
    }
}

fn forget(path: &Path) {
    if let Ok(mut live) = LIVE.lock() {
        live.retain(|p| p != path);
    }
}

/// Writes bytes to `path` through a unique temp file and a rename, so a crash or a concurrent
/// writer never leaves half a file.
///
/// # Errors
/// [`IoError::File`] naming `path` (never the temp file).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    let temp = TempFile::beside(path)?;
    std::fs::write(temp.path(), bytes).map_err(|e| IoError::file("write", path, e))?;
    temp.persist()
}

/// Removes every temp file in flight and exits with 130 on Ctrl-C or SIGTERM. Call once at
/// start; a second call is ignored.
pub fn remove_temp_files_on_signal() {
    let _ = ctrlc::set_handler(|| {
        // A sweep asked to finish its points in flight first: the first signal sets its flag,
        // a second one quits at once.
        if let Ok(slot) = DEFERRED_STOP.lock()
            && let Some(flag) = slot.as_ref()
            && !flag.swap(true, std::sync::atomic::Ordering::SeqCst)
        {
            eprintln!("\nstopping after the points in flight (Ctrl-C again to quit now)");
            return;
        }
        if let Ok(live) = LIVE.lock() {
            for p in live.iter() {
                let _ = std::fs::remove_file(p);
            }
        }
        std::process::exit(130);
    });
}

static DEFERRED_STOP: Mutex<Option<std::sync::Arc<std::sync::atomic::AtomicBool>>> =
    Mutex::new(None);

/// While the returned guard lives, the first Ctrl-C or SIGTERM sets `flag` instead of quitting
/// (a long run stops cleanly, keeping its finished work); a second one quits as usual.
pub fn defer_signal_to(flag: std::sync::Arc<std::sync::atomic::AtomicBool>) -> DeferredStop {
    if let Ok(mut slot) = DEFERRED_STOP.lock() {
        *slot = Some(flag);
    }
    DeferredStop(())
}

/// Restores the usual Ctrl-C behaviour when dropped.
#[must_use = "the deferral ends when the guard is dropped"]
pub struct DeferredStop(());

impl Drop for DeferredStop {
    fn drop(&mut self) {
        if let Ok(mut slot) = DEFERRED_STOP.lock() {
            *slot = None;
        }
    }
}

/// How many temp files are in flight (tests check that none is left).
pub fn temp_files_in_flight() -> usize {
    LIVE.lock().map_or(0, |l| l.len())
}

/// Encodes an image straight into a temp file beside `path` (no encoded copy in memory) and
/// moves it into place.
pub(crate) fn write_image(
    path: &Path,
    img: image::DynamicImage,
    format: image::ImageFormat,
) -> Result<(), IoError> {
    let temp = TempFile::beside(path)?;
    let file = open_reserved(temp.path()).map_err(|e| IoError::file("write", path, e))?;
    let mut out = std::io::BufWriter::new(file);
    img.write_to(&mut out, format).map_err(|e| IoError::Image {
        path: path.to_path_buf(),
        message: format!("cannot encode the {format:?} image: {e}"),
    })?;
    out.into_inner()
        .map_err(|e| IoError::file("write", path, e.into_error()))?;
    temp.persist()
}

pub(crate) fn size_mismatch(path: &Path) -> IoError {
    IoError::Image {
        path: path.to_path_buf(),
        message: "the pixel buffer does not match the image size".into(),
    }
}
