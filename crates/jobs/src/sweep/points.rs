//! One point of a sweep: its parameters (the job's own, by their flag names), its hash, and
//! its metrics: the job built from the parameters and evaluated as the command evaluates it
//! (`--json`'s object, flattened).

use std::collections::HashMap;
use std::path::Path;
use std::sync::Mutex;

use anyhow::{Result, anyhow};
use serde_json::Value;

use crate::{JobSpec, evaluate, params::params_of};
use udc_core::Progress;
use udc_core::sweep::hash::{point_hash, short_hash_of_digest};
use udc_core::sweep::{ParamValue, Points, SweepJob, SweepSpec};

/// Parameters whose values are input files: their content, not their name, enters the hash.
pub const FILE_PARAMS: [&str; 6] = ["design", "pattern", "spectral", "image", "photo", "hdr"];

/// The spec with every relative input file (a value of a [`FILE_PARAMS`] parameter, in the
/// base, an axis or a `with` list) joined onto `root`: a spec written for one working directory,
/// run from another.
pub fn inputs_under(spec: &SweepSpec, root: &Path) -> SweepSpec {
    let fix = |name: &str, v: &mut ParamValue| {
        if let ParamValue::Text(t) = v
            && FILE_PARAMS.contains(&name)
            && Path::new(t.as_str()).is_relative()
        {
            *t = root.join(t.as_str()).to_string_lossy().into_owned();
        }
    };
    let mut out = spec.clone();
    for (k, v) in &mut out.base {
        fix(k, v);
    }
    for axis in &mut out.axes {
        // A label axis's values are names, never files.
        if !axis.label {
            for v in axis.values.iter_mut().flatten() {
                fix(&axis.param, v);
            }
        }
        for (k, vals) in &mut axis.with {
            for v in vals {
                fix(k, v);
            }
        }
    }
    out
}

/// The job of a point from its parameters.
///
/// # Errors
/// An unknown parameter or a value of the wrong type, naming it.
pub fn job_of(job: SweepJob, params: &[(String, &ParamValue)]) -> Result<JobSpec> {
    JobSpec::from_params(
        job,
        &params_of(params.iter().map(|(k, v)| (k.as_str(), *v))),
    )
}

/// Base, axis and linked values of point `index` (label axes left out: they only name the
/// point), in a stable order (base first).
pub fn point_params<'a>(
    spec: &'a SweepSpec,
    points: &'a Points,
    index: u64,
) -> Vec<(String, &'a ParamValue)> {
    params_at(spec, points, &points.digits(index))
}

/// Base, axis and linked values at these value indices (one per axis).
fn params_at<'a>(
    spec: &'a SweepSpec,
    points: &'a Points,
    digits: &[usize],
) -> Vec<(String, &'a ParamValue)> {
    spec.base
        .iter()
        .map(|(k, v)| (k.clone(), v))
        .chain(
            points
                .flags_at(digits)
                .into_iter()
                .map(|(k, v)| (k.to_string(), v)),
        )
        .collect()
}

/// Content hashes of input files, read once per path.
#[derive(Default)]
pub struct FileDigests(Mutex<HashMap<String, String>>);

impl FileDigests {
    fn digest(&self, path: &str) -> Result<String> {
        if let Some(d) = self.0.lock().ok().and_then(|m| m.get(path).cloned()) {
            return Ok(d);
        }
        let p = Path::new(path);
        udc_io::safe_file::check_regular(p, "input file")?;
        // Streamed: an input file (an HDR scene, a large photo) is never held whole just to
        // be hashed.
        let d = std::fs::File::open(p)
            .and_then(short_hash_reader)
            .map_err(|e| anyhow!("cannot read {}: {e}", p.display()))?;
        if let Ok(mut m) = self.0.lock() {
            m.insert(path.to_string(), d.clone());
        }
        Ok(d)
    }
}

fn short_hash_reader(mut r: impl std::io::Read) -> std::io::Result<String> {
    use sha2::Digest;
    let mut hasher = sha2::Sha256::new();
    let mut buf = vec![0u8; 1 << 16];
    loop {
        let n = r.read(&mut buf)?;
        if n == 0 {
            return Ok(short_hash_of_digest(&hasher.finalize()));
        }
        hasher.update(buf.get(..n).unwrap_or_default());
    }
}

/// The point's identity: job, parameters and the content of the files it reads.
///
/// # Errors
/// An input file that cannot be read.
pub fn hash_of(
    job: SweepJob,
    params: &[(String, &ParamValue)],
    files: &FileDigests,
) -> Result<String> {
    let mut canon = Vec::with_capacity(params.len());
    for (name, value) in params {
        let mut text = value.to_arg();
        if FILE_PARAMS.contains(&name.as_str()) {
            text = format!("{text}@{}", files.digest(&text)?);
        }
        canon.push((name.clone(), text));
    }
    Ok(point_hash(job.as_str(), &canon))
}

/// What one point computed: the `--json` object and the hash of the design it resolved (the
/// point's hash for jobs without a display design).
pub struct PointOutput {
    /// The job's `--json` object.
    pub value: Value,
    /// Hash of the resolved design.
    pub design_hash: String,
}

/// Computes one point.
///
/// # Errors
/// The job's own error (an invalid value, an unreadable file, a refused size).
pub fn evaluate_point(job: &JobSpec, point_hash: &str, progress: &Progress) -> Result<PointOutput> {
    let report = evaluate(job, progress)?;
    Ok(PointOutput {
        value: report.json,
        design_hash: job.design_hash()?.unwrap_or_else(|| point_hash.to_string()),
    })
}

/// Checks a spec without running it: the base alone, and every value of every axis (with the
/// other axes at their first value), built into the job and checked (for display jobs, the
/// design resolved). Returns the number of points.
///
/// # Errors
/// The first value refused, naming its axis and the command's message.
pub fn check_points(spec: &SweepSpec) -> Result<u64> {
    let points = Points::new(spec)?;
    let check = |params: Vec<(String, &ParamValue)>, what: &str| -> Result<()> {
        job_of(spec.job, &params)
            .and_then(|job| job.check())
            .map_err(|e| anyhow!("{what}: {e:#}"))
    };
    let axes = points.names().len();
    for (k, name) in points.names().iter().enumerate() {
        for (j, v) in points.axis(k).iter().enumerate() {
            let mut digits = vec![0; axes];
            digits[k] = j;
            let params = params_at(spec, &points, &digits);
            check(params, &format!("axis `{name}` value `{}`", v.to_arg()))?;
        }
    }
    if axes == 0 {
        check(params_at(spec, &points, &[]), "base")?;
    }
    Ok(points.count())
}
