//! The document: the design being edited, where it lives on disk, and its undo history (the
//! studio's one [`History`]). Undo points are recorded per committed edit (a whole drag is one
//! edit), never per frame.

use std::path::PathBuf;

use crate::app::history::{History, Snapshot};
use crate::core::Design;

impl Snapshot for Design {
    fn same(&self, other: &Self) -> bool {
        self == other
    }
}

/// The design being edited in the display workspace, its file and its undo/redo history.
#[derive(Debug, Clone)]
pub struct Document {
    history: History<Design>,
    /// The file it was opened from or saved to.
    pub path: Option<PathBuf>,
}

impl Document {
    /// A clean document (nothing to undo, not dirty) of `design`, whose file is `path` if any.
    pub fn new(design: Design, path: Option<PathBuf>) -> Self {
        Document {
            history: History::new(design),
            path,
        }
    }

    /// The design as currently edited.
    pub fn design(&self) -> &Design {
        self.history.current()
    }

    /// Applies a committed edit as one undo step. Returns whether anything changed.
    /// Emitters left on cells the edit opened are removed (they must sit on closed cells).
    pub fn edit(&mut self, mut design: Design) -> bool {
        design.reconcile_subpixels();
        self.history.edit(design)
    }

    /// Whether there is an edit to undo.
    pub fn can_undo(&self) -> bool {
        self.history.can_undo()
    }

    /// Whether there is an undone edit to redo.
    pub fn can_redo(&self) -> bool {
        self.history.can_redo()
    }

    /// Steps back one edit. Returns false when there is nothing to undo.
    pub fn undo(&mut self) -> bool {
        self.history.undo()
    }

    /// Re-applies the edit last undone. Returns false when there is nothing to redo.
    pub fn redo(&mut self) -> bool {
        self.history.redo()
    }

    /// Replaces the whole document (open, new, preset), keeping the old design undoable so a
    /// mistaken open loses nothing.
    pub fn replace(&mut self, mut design: Design, path: Option<PathBuf>) {
        design.reconcile_subpixels();
        self.history.replace(design);
        self.path = path;
    }

    /// Records that the current design is now on disk at `path`.
    pub fn mark_saved(&mut self, path: PathBuf) {
        self.history.mark_saved();
        self.path = Some(path);
    }

    /// Whether the design differs from what was last opened, loaded (a preset) or saved.
    pub fn is_dirty(&self) -> bool {
        self.history.is_dirty()
    }

    /// Title for the window: name, file and a star when unsaved.
    pub fn title(&self) -> String {
        let file = self
            .path
            .as_ref()
            .and_then(|p| p.file_name())
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "unsaved".into());
        let star = if self.is_dirty() { " *" } else { "" };
        format!("{} ({file}){star} — UDC Studio", self.design().name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::design::TilingMode;

    #[test]
    fn undo_and_redo_walk_the_history() {
        let mut doc = Document::new(Design::default_toled(), None);
        let a = doc.design().clone();
        let mut b = a.clone();
        b.tiling.mode = TilingMode::RandomD4;
        assert!(doc.edit(b.clone()));
        assert!(
            !doc.edit(b.clone()),
            "an edit that changes nothing is not an undo step"
        );
        assert!(doc.is_dirty());
        assert!(doc.undo());
        assert_eq!(doc.design(), &a);
        assert!(doc.redo());
        assert_eq!(doc.design(), &b);
        assert!(!doc.redo());
        // Loading another design is undoable but not an unsaved change.
        let mut c = b.clone();
        c.tiling.seed = 9;
        doc.replace(c.clone(), None);
        assert!(!doc.is_dirty());
        assert!(doc.undo());
        assert_eq!(doc.design(), &b);
        assert!(doc.redo());
        doc.mark_saved("x.json".into());
        assert!(!doc.is_dirty());
        assert!(doc.undo());
        assert!(doc.is_dirty());
    }
}
