//! OASIS (SEMI P39, `.oas`) masks: a writer for the export and a reader for the import.
//!
//! No maintained Rust crate writes OASIS: `libreda-oasis` (0.0.x, AGPL-3.0) would bind the
//! studio's licence and brings its own layout database. The format's subset used here is
//! small and written to the standard; every export is read back by KLayout and gdstk in the
//! test suite.

mod encode;
mod read;
mod write;

pub(crate) use read::read;
pub(crate) use write::{estimate, write};
