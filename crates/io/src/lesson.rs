//! Lesson files (TOML, [`udc_core::lesson`]): read, checked against the built-in presets, and
//! the lessons shipped in `presets/lessons/`. Every refusal is one line naming the step
//! (counted from 1) and the field.

use std::path::{Path, PathBuf};

use udc_core::lesson::Lesson;

use crate::error::IoError;

/// `(file name, its text)` for lesson files in `presets/lessons/`, built into the binary.
macro_rules! lessons {
    ($($file:literal),* $(,)?) => {
        &[$(($file, include_str!(concat!("../../../presets/lessons/", $file)))),*]
    };
}

/// The lessons shipped with the studio, in teaching order: `(file name, TOML text)`.
pub const SHIPPED: &[(&str, &str)] = lessons![
    "01-slit.toml",
    "02-circle.toml",
    "03-double-slit.toml",
    "04-grating.toml",
    "05-convolution.toml",
    "06-random-tiling.toml",
    "07-sampling.toml",
    "08-colour.toml",
    "09-mystery.toml",
    "10-draw.toml",
    "11-microlens-arrays.toml",
];

/// The largest lesson file read, bytes (a lesson is a page of text).
const MAX_BYTES: u64 = 1 << 20;

/// A lesson from its TOML `text`, checked; errors name the step and the field.
///
/// # Errors
/// TOML that does not parse, a field of the wrong type or unknown, a broken rule of
/// [`Lesson::check`] (an unknown preset included): one line, without the file's name.
pub fn parse_lesson(text: &str) -> Result<Lesson, String> {
    let de = toml::Deserializer::parse(text).map_err(|e| one_line(&e.to_string()))?;
    let lesson: Lesson = serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let message = one_line(&e.into_inner().to_string());
        if path == "." {
            message
        } else {
            format!("{}: {message}", readable_path(&path))
        }
    })?;
    lesson
        .check(|name| crate::design::presets::load_preset(name).is_ok())
        .map_err(|e| e.to_string())?;
    Ok(lesson)
}

/// Reads and checks the lesson file at `path`. A mystery aperture's design file (`mystery_file`) is found beside the lesson and must load:
/// its path becomes absolute in the lesson returned.
///
/// # Errors
/// A file that cannot be read (or is over a megabyte), [`parse_lesson`]'s refusal, or a
/// mystery design file that does not load, with the lesson file named.
pub fn read_lesson(path: &Path) -> Result<Lesson, IoError> {
    let refuse = |message: String| IoError::Lesson {
        path: path.to_path_buf(),
        message,
    };
    let text = crate::safe_file::read_text_bounded(path, MAX_BYTES, "lesson")?;
    let mut lesson = parse_lesson(&text).map_err(refuse)?;
    let dir = path.parent().unwrap_or(Path::new(""));
    for (i, step) in lesson.steps.iter_mut().enumerate() {
        if let Some(file) = &mut step.mystery_file {
            let full = dir.join(&*file);
            crate::design::file::load_design(&full).map_err(|e| {
                refuse(format!(
                    "step {}, mystery_file: {}",
                    i + 1,
                    one_line(&e.to_string())
                ))
            })?;
            *file = full;
        }
    }
    Ok(lesson)
}

/// The shipped lessons, parsed once per process (parsing checks every preset a lesson
/// names, too slow for every frame of the list); a shipped lesson that does not parse is a
/// build bug, which the lesson tests catch.
pub fn shipped() -> &'static [(PathBuf, Result<Lesson, String>)] {
    static PARSED: std::sync::OnceLock<Vec<(PathBuf, Result<Lesson, String>)>> =
        std::sync::OnceLock::new();
    PARSED.get_or_init(|| {
        SHIPPED
            .iter()
            .map(|(name, text)| (PathBuf::from(name), parse_lesson(text)))
            .collect()
    })
}

/// `step[2].question.tolerance` as `step 3, question.tolerance`.
fn readable_path(path: &str) -> String {
    if let Some(rest) = path.strip_prefix("step[")
        && let Some((index, field)) = rest.split_once(']')
        && let Ok(i) = index.parse::<usize>()
    {
        let field = field.trim_start_matches('.');
        return if field.is_empty() {
            format!("step {}", i + 1)
        } else {
            format!("step {}, {field}", i + 1)
        };
    }
    path.to_owned()
}

/// toml's several-line message (a snippet of the file) as one line.
fn one_line(message: &str) -> String {
    message
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('|') && !l.chars().all(|c| c == '^'))
        .collect::<Vec<_>>()
        .join(" ")
}
