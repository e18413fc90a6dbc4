//! The one undo history of the studio's workspaces: the value being edited, the steps to undo
//! and redo, and what was last saved. Display keeps its design in one (inside its document),
//! Phase its phase design.
//!
//! A control may edit the value live ([`History::current_mut`]) while a drag or a text edit is
//! under way; the caller commits once the gesture ends, so a whole drag is one undo step, never
//! one step per frame.

/// Most undo steps kept (a design is ~10 kB, so this is a few MB at most).
pub const MAX_UNDO: usize = 200;

/// A value the history can hold: cloned per step and compared to tell a change.
pub trait Snapshot: Clone {
    /// Whether `self` and `other` are the same state (NaN-aware where the value holds floats a
    /// user can type: a NaN field must not look like a change every frame).
    fn same(&self, other: &Self) -> bool;
}

/// The value being edited with its undo/redo history and its last saved state.
#[derive(Debug, Clone)]
pub struct History<T> {
    current: T,
    /// The last committed state: the step an undo returns to from a pending live edit.
    committed: T,
    /// The state last opened, loaded or saved: the value is dirty when it differs.
    saved: T,
    undo: Vec<T>,
    redo: Vec<T>,
}

impl<T: Snapshot> History<T> {
    /// A clean history of `value`: nothing to undo, not dirty.
    pub fn new(value: T) -> Self {
        History {
            committed: value.clone(),
            saved: value.clone(),
            current: value,
            undo: Vec::new(),
            redo: Vec::new(),
        }
    }

    /// The value as currently edited (including a live edit not yet committed).
    pub fn current(&self) -> &T {
        &self.current
    }

    /// The value to edit live; [`History::commit`] makes the change one undo step.
    pub fn current_mut(&mut self) -> &mut T {
        &mut self.current
    }

    /// The last committed value (what autosave writes: never a half-finished drag).
    pub fn committed(&self) -> &T {
        &self.committed
    }

    /// Records the live edits since the last commit as one undo step. Returns whether there
    /// were any.
    pub fn commit(&mut self) -> bool {
        if self.current.same(&self.committed) {
            return false;
        }
        let previous = std::mem::replace(&mut self.committed, self.current.clone());
        self.undo.push(previous);
        if self.undo.len() > MAX_UNDO {
            self.undo.remove(0);
        }
        self.redo.clear();
        true
    }

    /// Replaces the value as one undo step (after committing any pending live edit as its own
    /// step). Returns whether anything changed.
    pub fn edit(&mut self, value: T) -> bool {
        let pending = self.commit();
        self.current = value;
        self.commit() || pending
    }

    /// Replaces the whole value (open, new, preset), keeping the old one undoable so a mistaken
    /// open loses nothing; the new value counts as saved.
    pub fn replace(&mut self, value: T) {
        self.edit(value);
        self.mark_saved();
    }

    /// Whether there is a change to undo, including a live edit not yet committed.
    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty() || !self.current.same(&self.committed)
    }

    /// Whether there is an undone change to redo.
    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// Steps back one change (a pending live edit is committed first, then undone). Returns
    /// false when there is nothing to undo.
    pub fn undo(&mut self) -> bool {
        self.commit();
        let Some(previous) = self.undo.pop() else {
            return false;
        };
        self.redo
            .push(std::mem::replace(&mut self.committed, previous));
        self.current = self.committed.clone();
        true
    }

    /// Re-applies the change last undone. Returns false when there is nothing to redo.
    pub fn redo(&mut self) -> bool {
        self.commit();
        let Some(next) = self.redo.pop() else {
            return false;
        };
        self.undo.push(std::mem::replace(&mut self.committed, next));
        self.current = self.committed.clone();
        true
    }

    /// Records that the committed value is now saved.
    pub fn mark_saved(&mut self) {
        self.saved = self.committed.clone();
    }

    /// Whether the value differs from what was last opened, loaded or saved.
    pub fn is_dirty(&self) -> bool {
        !self.current.same(&self.saved)
    }

    /// Whether the committed value differs from what was last saved (what an autosave asks).
    pub fn is_committed_unsaved(&self) -> bool {
        !self.committed.same(&self.saved)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Clone, PartialEq)]
    struct V(f64);

    impl Snapshot for V {
        fn same(&self, other: &Self) -> bool {
            self.0 == other.0 || (self.0.is_nan() && other.0.is_nan())
        }
    }

    #[test]
    fn undo_and_redo_walk_the_committed_steps() {
        let mut h = History::new(V(1.0));
        assert!(!h.can_undo() && !h.can_redo() && !h.is_dirty());
        assert!(h.edit(V(2.0)));
        assert!(
            !h.edit(V(2.0)),
            "an edit that changes nothing is not a step"
        );
        assert!(h.edit(V(3.0)));
        assert!(h.undo());
        assert_eq!(h.current(), &V(2.0));
        assert!(h.undo());
        assert_eq!(h.current(), &V(1.0));
        assert!(!h.undo());
        assert!(h.redo());
        assert_eq!(h.current(), &V(2.0));
        // A new edit drops what could be redone.
        assert!(h.edit(V(5.0)));
        assert!(!h.can_redo());
    }

    #[test]
    fn a_live_edit_is_one_step_when_committed_and_undoable_before() {
        let mut h = History::new(V(1.0));
        for v in [1.5, 1.7, 2.0] {
            h.current_mut().0 = v;
        }
        assert!(h.can_undo(), "an uncommitted live edit can be undone");
        assert_eq!(h.committed(), &V(1.0), "autosave never sees half a drag");
        assert!(h.undo(), "undo commits the drag, then undoes it whole");
        assert_eq!(h.current(), &V(1.0));
        assert!(h.redo());
        assert_eq!(h.current(), &V(2.0));
    }

    #[test]
    fn nan_is_not_a_change_every_frame() {
        let mut h = History::new(V(f64::NAN));
        assert!(!h.commit());
        assert!(!h.can_undo());
        assert!(!h.is_dirty());
    }

    #[test]
    fn replace_is_undoable_but_clean_and_saving_marks_clean() {
        let mut h = History::new(V(1.0));
        h.edit(V(2.0));
        assert!(h.is_dirty());
        h.replace(V(9.0));
        assert!(!h.is_dirty(), "an opened design is not an unsaved change");
        assert!(h.undo());
        assert_eq!(h.current(), &V(2.0));
        assert!(h.is_dirty());
        h.mark_saved();
        assert!(!h.is_dirty() && !h.is_committed_unsaved());
    }

    #[test]
    fn the_history_is_bounded() {
        let mut h = History::new(V(0.0));
        for i in 1..=(MAX_UNDO + 50) {
            h.edit(V(i as f64));
        }
        let mut steps = 0;
        while h.undo() {
            steps += 1;
        }
        assert_eq!(steps, MAX_UNDO);
    }
}
