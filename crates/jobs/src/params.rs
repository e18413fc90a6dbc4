//! A job from named parameters (a sweep point, a Python call): serde over the job's struct,
//! with its defaults, every unknown name refused and every refusal naming its parameter.

use std::fmt::Display;
use std::str::FromStr;

use anyhow::{Result, anyhow};
use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::{Map, Value};
use udc_core::sweep::ParamValue;

/// Named parameters: the CLI's flag names without `--` (`pitch-um`), each with its value.
pub type Params = Map<String, Value>;

/// A parameter's value as JSON: a switch, a whole number, a real number or a text. A number
/// that is not finite, which JSON cannot hold, goes as its text (`NaN`, `inf`), so that the
/// parameter's check refuses it by name rather than it being lost.
fn param_value_json(value: &ParamValue) -> Value {
    match value {
        ParamValue::Bool(b) => Value::Bool(*b),
        ParamValue::Int(i) => Value::from(*i),
        ParamValue::Float(f) if !f.is_finite() => Value::String(f.to_string()),
        ParamValue::Float(f) => Value::from(*f),
        ParamValue::Text(t) => Value::String(t.clone()),
    }
}

/// Parameters from name–value pairs in order; a name given again makes a list (as a flag
/// given again on the command line), and `false` leaves a parameter at its default (a switch
/// off; in a `with` list, a value this point does not set).
pub fn params_of<'a>(pairs: impl IntoIterator<Item = (&'a str, &'a ParamValue)>) -> Params {
    let mut out = Params::new();
    for (name, value) in pairs {
        if *value == ParamValue::Bool(false) {
            continue;
        }
        let v = param_value_json(value);
        match out.get_mut(name) {
            Some(Value::Array(list)) => list.push(v),
            Some(old) => *old = Value::Array(vec![old.take(), v]),
            None => {
                out.insert(name.to_string(), v);
            }
        }
    }
    out
}

/// A job's parameters from a [`Params`].
pub trait FromParams: Sized {
    /// The job with these parameters over its defaults.
    ///
    /// # Errors
    /// An unknown name (with the names there are) or a value of the wrong type, naming it.
    fn from_params(params: &Params) -> Result<Self>;
}

impl<T: DeserializeOwned + Serialize + Default> FromParams for T {
    fn from_params(params: &Params) -> Result<Self> {
        let Value::Object(defaults) = serde_json::to_value(T::default())? else {
            return Err(anyhow!("a job's parameters are not a map"));
        };
        let mut all = defaults.clone();
        for (name, value) in params {
            match all.get_mut(name) {
                Some(slot) => *slot = value.clone(),
                None => {
                    let known: Vec<&str> = defaults.keys().map(String::as_str).collect();
                    return Err(anyhow!(
                        "unknown parameter `{name}` (expected one of: {})",
                        known.join(", ")
                    ));
                }
            }
        }
        serde_json::from_value(Value::Object(all)).map_err(|e| {
            // serde loses the field's name inside a flattened struct: the parameter that fails
            // on its own over the defaults is the one to name.
            let culprit = params.iter().find(|(name, value)| {
                let mut one = defaults.clone();
                one.insert((*name).clone(), (*value).clone());
                serde_json::from_value::<T>(Value::Object(one)).is_err()
            });
            match culprit {
                Some((name, _)) => anyhow!("parameter `{name}`: {e}"),
                None => anyhow!("parameters: {e}"),
            }
        })
    }
}

/// The text of a scalar (a number or a word alike: `0.002`, `matched`).
fn scalar_text(value: &Value) -> Option<String> {
    match value {
        Value::String(s) => Some(s.clone()),
        Value::Number(n) => Some(n.to_string()),
        Value::Bool(b) => Some(b.to_string()),
        _ => None,
    }
}

/// A closed set by its strum name (`additive`, `p99`), the name the CLI takes.
pub mod named {
    use serde::de::Error as _;
    use serde::{Deserialize, Deserializer, Serializer};
    use strum::VariantArray;

    /// Writes the member's name.
    ///
    /// # Errors
    /// The serializer's.
    pub fn serialize<S: Serializer, T: Copy + Into<&'static str>>(
        value: &T,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        s.serialize_str((*value).into())
    }

    /// Reads a member by its name.
    ///
    /// # Errors
    /// A name that is no member's, listing the names.
    pub fn deserialize<'de, D: Deserializer<'de>, T>(d: D) -> Result<T, D::Error>
    where
        T: VariantArray + Copy + Into<&'static str>,
    {
        let text = String::deserialize(d)?;
        T::VARIANTS
            .iter()
            .copied()
            .find(|v| Into::<&'static str>::into(*v) == text)
            .ok_or_else(|| {
                let names: Vec<&'static str> = T::VARIANTS.iter().map(|v| (*v).into()).collect();
                D::Error::custom(format!(
                    "unknown value `{text}` (expected one of: {})",
                    names.join(", ")
                ))
            })
    }
}

/// A value the CLI parses from its text (`--denoise-sigma2 matched|table|S`), optional: a word
/// or a number, or nothing.
pub mod optional_text {
    use super::{Display, FromStr, Value, scalar_text};
    use serde::de::Error as _;
    use serde::{Deserialize, Deserializer, Serializer};

    /// Writes the value as the CLI spells it, or nothing.
    ///
    /// # Errors
    /// The serializer's.
    pub fn serialize<S: Serializer, T: Display>(
        value: &Option<T>,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        match value {
            Some(v) => s.serialize_str(&v.to_string()),
            None => s.serialize_none(),
        }
    }

    /// Reads a value from its text (a number is its text), or nothing.
    ///
    /// # Errors
    /// A value its parser refuses, with the parser's message.
    pub fn deserialize<'de, D: Deserializer<'de>, T>(d: D) -> Result<Option<T>, D::Error>
    where
        T: FromStr,
        T::Err: Display,
    {
        let value = Value::deserialize(d)?;
        if value.is_null() {
            return Ok(None);
        }
        let text = scalar_text(&value)
            .ok_or_else(|| D::Error::custom(format!("expected a word or a number, not {value}")))?;
        text.parse().map(Some).map_err(D::Error::custom)
    }
}

/// A list that may be given as one value, a list, or (for numbers) a comma-separated text
/// (`"250,650,1600"`), as the CLI takes `--photons 250,650` or a repeated flag.
pub mod list {
    use super::{FromStr, Value, scalar_text};
    use serde::de::{DeserializeOwned, Error as _};
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    /// Writes the list.
    ///
    /// # Errors
    /// The serializer's.
    pub fn serialize<S: Serializer, T: Serialize>(value: &[T], s: S) -> Result<S::Ok, S::Error> {
        value.serialize(s)
    }

    /// Reads one value, a list, or a comma-separated text.
    ///
    /// # Errors
    /// An item of the wrong type.
    pub fn deserialize<'de, D: Deserializer<'de>, T>(d: D) -> Result<Vec<T>, D::Error>
    where
        T: FromStr + DeserializeOwned,
        T::Err: std::fmt::Display,
    {
        let items = match Value::deserialize(d)? {
            Value::Array(items) => items,
            Value::Null => Vec::new(),
            Value::String(text) => text
                .split(',')
                .map(|t| Value::String(t.trim().to_string()))
                .collect(),
            other => vec![other],
        };
        items
            .into_iter()
            .map(|item| match item {
                Value::String(_) | Value::Number(_) | Value::Bool(_) => {
                    let text = scalar_text(&item).unwrap_or_default();
                    text.parse::<T>()
                        .map_err(|e| D::Error::custom(format!("`{text}`: {e}")))
                }
                other => serde_json::from_value(other).map_err(D::Error::custom),
            })
            .collect()
    }
}

/// A list of paths given as one path or a list (a comma is part of a path).
pub mod paths {
    use std::path::PathBuf;

    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    /// Writes the list.
    ///
    /// # Errors
    /// The serializer's.
    pub fn serialize<S: Serializer>(value: &[PathBuf], s: S) -> Result<S::Ok, S::Error> {
        value.serialize(s)
    }

    /// Reads one path or a list of them.
    ///
    /// # Errors
    /// An item that is not a path.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<PathBuf>, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum OneOrMany {
            One(PathBuf),
            Many(Vec<PathBuf>),
        }
        Ok(match Option::<OneOrMany>::deserialize(d)? {
            None => Vec::new(),
            Some(OneOrMany::One(p)) => vec![p],
            Some(OneOrMany::Many(v)) => v,
        })
    }
}
