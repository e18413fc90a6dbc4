//! The core's closed sets as clap values. The core names its enums' members with strum (the
//! name, and the doc comment as help) and knows nothing of clap; this parser offers them as
//! `clap::ValueEnum` would, with the same possible values, help and errors.

use std::ffi::OsStr;

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use strum::{EnumMessage, VariantArray};

/// A clap value parser over some members of a closed set.
#[derive(Clone)]
pub struct Choice<T: 'static>(&'static [T]);

/// Every member of `T` (strum's `VariantArray`), in declaration order.
pub fn choice<T: VariantArray>() -> Choice<T> {
    Choice(T::VARIANTS)
}

/// Only `members`, for a set whose other members a user cannot pick (a design's "custom"
/// optics are edited values, not a name).
pub fn choice_of<T>(members: &'static [T]) -> Choice<T> {
    Choice(members)
}

/// A member's help as clap's derive writes a doc comment: its first paragraph on one line,
/// without the closing full stop, and without rustdoc's link brackets (`[`AdditiveGain`]` reads
/// `AdditiveGain`), which mean nothing on a terminal.
fn help(doc: &str) -> String {
    let paragraph = doc.split("\n\n").next().unwrap_or_default();
    let line = paragraph
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
        .replace("[`", "`")
        .replace("`]", "`");
    match line.strip_suffix('.') {
        Some(stripped) if !stripped.ends_with('.') => stripped.to_owned(),
        _ => line,
    }
}

impl<T> Choice<T>
where
    T: Copy + Into<&'static str> + EnumMessage,
{
    fn possible(&self) -> impl Iterator<Item = PossibleValue> + '_ {
        self.0.iter().map(|&member| {
            let value = PossibleValue::new(member.into());
            match member.get_documentation() {
                Some(doc) => value.help(help(doc)),
                None => value,
            }
        })
    }
}

impl<T> TypedValueParser for Choice<T>
where
    T: Copy + Send + Sync + Into<&'static str> + EnumMessage + 'static,
{
    type Value = T;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &OsStr,
    ) -> Result<T, clap::Error> {
        // clap's own parser words the refusal ("invalid value … [possible values: …]").
        let word = PossibleValuesParser::new(self.possible()).parse_ref(cmd, arg, value)?;
        self.0
            .iter()
            .copied()
            .find(|&member| member.into() == word.as_str())
            .ok_or_else(|| clap::Error::new(clap::error::ErrorKind::InvalidValue).with_cmd(cmd))
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(self.possible()))
    }
}
