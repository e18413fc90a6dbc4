//! One line for the user: what happened, and whether it went wrong. Status bars and the
//! workspaces' message lines all hold a [`Notice`].

/// Whether a notice reports a failure.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoticeKind {
    /// Something happened as asked; shown in the normal (or dimmed) text colour.
    Info,
    /// Something failed; shown in the theme's error colour.
    Error,
}

/// A message for the status bar or a panel's message line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Notice {
    /// The message, one line.
    pub text: String,
    /// Whether it reports a failure, which decides its colour.
    pub kind: NoticeKind,
}

impl Notice {
    /// A notice that reports success or progress.
    pub fn info(text: impl Into<String>) -> Self {
        Notice {
            text: text.into(),
            kind: NoticeKind::Info,
        }
    }

    /// A notice that reports a failure.
    pub fn error(text: impl Into<String>) -> Self {
        Notice {
            text: text.into(),
            kind: NoticeKind::Error,
        }
    }

    /// Whether it reports a failure (and is drawn in the error colour).
    pub fn is_error(&self) -> bool {
        self.kind == NoticeKind::Error
    }
}
