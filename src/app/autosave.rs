//! Keeping a workspace's value on disk without being asked: written off the UI thread a few
//! seconds after it changes (the shell's `autosave_every`), and once more, blocking, on exit.
//! Display autosaves its design beside the user's files; Phase keeps its design this way.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crate::app::history::Snapshot;
use crate::app::job::Job;
use crate::io::IoError;

/// Writes `value` to `path` (creating the folder).
pub type WriteFn<T> = fn(&Path, &T) -> Result<(), IoError>;

/// The autosave of one value (see the module docs).
pub struct Autosave<T> {
    /// The file; none in tests without a data directory (nothing is written).
    path: Option<PathBuf>,
    /// The value last handed to a write (or read from the file at start).
    written: Option<T>,
    last: Instant,
    task: Option<Job<()>>,
    write: WriteFn<T>,
}

impl<T: Snapshot + Send + 'static> Autosave<T> {
    /// Autosaves to `path` with `write`; `written` is what the file holds already, if known.
    pub fn new(path: Option<PathBuf>, written: Option<T>, write: WriteFn<T>) -> Self {
        Autosave {
            path,
            written,
            last: Instant::now(),
            task: None,
            write,
        }
    }

    /// The file written to.
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// Called every frame with the value to keep: writes it when it changed and `every` has
    /// passed since the last write (asking `ctx` to wake the UI then). Returns the message of
    /// a write that failed.
    pub fn tick(&mut self, value: &T, every: Duration, ctx: &egui::Context) -> Option<String> {
        let failed = match self.task.as_ref().and_then(Job::poll) {
            Some(done) => {
                self.task = None;
                done.err().map(|e| format!("autosave failed: {e}"))
            }
            None => None,
        };
        let changed = !self.written.as_ref().is_some_and(|w| w.same(value));
        if self.task.is_some() || !changed {
            return failed;
        }
        let Some(path) = self.path.clone() else {
            return failed;
        };
        let due = self.last + every;
        let now = Instant::now();
        if now < due {
            ctx.request_repaint_after(due - now);
            return failed;
        }
        self.written = Some(value.clone());
        self.last = now;
        let value = value.clone();
        let write = self.write;
        let wake = ctx.clone();
        self.task = Some(Job::spawn(
            "autosave",
            move || wake.request_repaint(),
            move |_| write(&path, &value),
        ));
        failed
    }

    /// Writes `value` now, on this thread (on exit). Returns whether it was written.
    pub fn save_now_blocking(&mut self, value: &T) -> bool {
        let Some(path) = &self.path else {
            return false;
        };
        let ok = (self.write)(path, value).is_ok();
        if ok {
            self.written = Some(value.clone());
        }
        ok
    }
}

/// Creates the folder of `path` if it is missing.
///
/// # Errors
/// [`IoError::File`] when the folder cannot be created.
pub fn create_parent(path: &Path) -> Result<(), IoError> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => {
            std::fs::create_dir_all(dir).map_err(|cause| IoError::File {
                action: "create the autosave folder",
                path: dir.to_path_buf(),
                cause,
            })
        }
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Clone, PartialEq)]
    struct V(u32);

    impl Snapshot for V {
        fn same(&self, other: &Self) -> bool {
            self == other
        }
    }

    fn write(path: &Path, v: &V) -> Result<(), IoError> {
        create_parent(path)?;
        std::fs::write(path, v.0.to_string()).map_err(|cause| IoError::File {
            action: "write the value",
            path: path.to_path_buf(),
            cause,
        })
    }

    /// Ticks until the write in flight has finished; returns what the last tick reported.
    fn settle(a: &mut Autosave<V>, v: &V, ctx: &egui::Context) -> Option<String> {
        for _ in 0..1000 {
            let failed = a.tick(v, Duration::ZERO, ctx);
            if failed.is_some() || a.task.is_none() {
                return failed;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        panic!("the autosave never finished");
    }

    #[test]
    fn writes_a_changed_value_once_it_is_due_and_not_before() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("sub").join("kept.txt");
        let ctx = egui::Context::default();
        let mut a = Autosave::new(Some(path.clone()), Some(V(1)), write);
        assert_eq!(a.tick(&V(1), Duration::ZERO, &ctx), None);
        assert!(
            a.task.is_none() && !path.exists(),
            "an unchanged value is not written"
        );
        a.tick(&V(2), Duration::from_secs(3600), &ctx);
        assert!(a.task.is_none(), "a change waits for the interval");
        a.last -= Duration::from_secs(3600);
        a.tick(&V(2), Duration::from_secs(3600), &ctx);
        assert_eq!(settle(&mut a, &V(2), &ctx), None);
        assert_eq!(std::fs::read_to_string(&path).expect("written"), "2");
        assert!(a.save_now_blocking(&V(3)));
        assert_eq!(std::fs::read_to_string(&path).expect("written"), "3");
    }

    #[test]
    fn a_failed_write_is_reported_and_nothing_without_a_path() {
        let dir = tempfile::tempdir().expect("temp dir");
        let blocker = dir.path().join("a-file");
        std::fs::write(&blocker, "not a folder").expect("write");
        let ctx = egui::Context::default();
        let mut a = Autosave::new(Some(blocker.join("kept.txt")), None, write);
        a.tick(&V(1), Duration::ZERO, &ctx);
        let failed = settle(&mut a, &V(1), &ctx).expect("the write fails");
        assert!(failed.starts_with("autosave failed"), "{failed}");
        let mut none = Autosave::new(None, None, write);
        assert_eq!(none.tick(&V(1), Duration::ZERO, &ctx), None);
        assert!(none.task.is_none());
        assert!(!none.save_now_blocking(&V(1)));
    }
}
