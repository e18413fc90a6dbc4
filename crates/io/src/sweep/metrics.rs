//! Metrics are the numbers of a job's `--json` output, named by their path: objects by key,
//! lists of named things (channels, strategies, runs) by the thing's name or, lacking one, its
//! index: `channels.G.auc_radial_min`, `runs.0.psnr_db`. A pattern may use `*` for one segment.

use serde_json::Value;

use crate::error::SpecError;

/// Every numeric scalar of `value`, with its path; lists of numbers (curves) are left out.
pub fn flatten_metrics(value: &Value) -> Vec<(String, f64)> {
    let mut out = Vec::new();
    walk(value, String::new(), &mut out);
    out
}

fn walk(v: &Value, path: String, out: &mut Vec<(String, f64)>) {
    let join = |k: &str| {
        if path.is_empty() {
            k.to_string()
        } else {
            format!("{path}.{k}")
        }
    };
    match v {
        Value::Number(n) => {
            if let Some(f) = n.as_f64() {
                out.push((path, f));
            }
        }
        Value::Object(map) => {
            for (k, x) in map {
                walk(x, join(k), out);
            }
        }
        Value::Array(items) if items.iter().any(Value::is_object) => {
            for (i, x) in items.iter().enumerate() {
                let name = ["name", "strategy", "label"]
                    .iter()
                    .find_map(|k| x.get(*k).and_then(Value::as_str))
                    .map_or_else(|| i.to_string(), str::to_string);
                walk(x, join(&name), out);
            }
        }
        _ => {}
    }
}

/// Whether a metric path matches a pattern (`*` matches one whole segment).
pub fn matches(pattern: &str, path: &str) -> bool {
    let p: Vec<&str> = pattern.split('.').collect();
    let q: Vec<&str> = path.split('.').collect();
    p.len() == q.len() && p.iter().zip(&q).all(|(a, b)| *a == "*" || a == b)
}

/// The metric columns of a sweep: the flattened metrics of a first point that match the
/// patterns, in pattern order, then in the output's order.
///
/// # Errors
/// [`SpecError::UnknownMetric`] for a pattern that matches nothing, with the metrics that exist.
pub fn select_columns(
    patterns: &[String],
    flat: &[(String, f64)],
) -> Result<Vec<String>, SpecError> {
    let mut out: Vec<String> = Vec::new();
    for p in patterns {
        let mut any = false;
        for (name, _) in flat {
            if matches(p, name) {
                any = true;
                if !out.contains(name) {
                    out.push(name.clone());
                }
            }
        }
        if !any {
            return Err(SpecError::UnknownMetric {
                pattern: p.clone(),
                available: flat.iter().map(|(n, _)| n.clone()).collect(),
            });
        }
    }
    Ok(out)
}
