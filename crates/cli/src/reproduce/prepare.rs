//! From a shipped spec to the spec a run executes: the repository found, relative input files
//! named from it, and for `--quick` the axes trimmed and the photos replaced by small copies.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};

use super::catalog::{Part, QuickPlan, ResultId};
use udc_core::psf::route::Backend;
use udc_core::sweep::{ParamValue, SweepSpec};
use udc_io::sweep::spec_file::load_spec;

/// Where the specs live, relative to the repository.
pub const SPEC_DIR: &str = "presets/reproduce";

/// Side of the quick photos, pixels (the test set's 512² halved).
pub const QUICK_SIDE_PX: u32 = 256;

/// The repository the specs and their input files are in: the working directory or one above
/// it (a user in the checkout), the running binary's folders (`target/release`), where a package
/// installs them (`/usr/share/udc-studio`), or the source tree it was built from.
///
/// # Errors
/// None of them holds `presets/reproduce/<spec>`.
pub fn repo_root(first_spec: &str) -> Result<PathBuf> {
    let mut candidates: Vec<PathBuf> = Vec::new();
    if let Ok(cwd) = std::env::current_dir() {
        candidates.extend(cwd.ancestors().take(4).map(Path::to_path_buf));
    }
    if let Ok(exe) = std::env::current_exe() {
        candidates.extend(exe.ancestors().skip(1).take(4).map(Path::to_path_buf));
    }
    candidates.extend(udc_io::installed_data_dir());
    candidates.push(udc_io::source_tree().to_path_buf());
    candidates
        .iter()
        .find(|d| d.join(SPEC_DIR).join(first_spec).is_file())
        .cloned()
        .ok_or_else(|| {
            anyhow!(
                "cannot find {SPEC_DIR}/{first_spec} in the working directory, beside the \
                 program or in {}: run from the repository",
                udc_io::source_tree().display()
            )
        })
}

/// The spec of one part as it runs: read from the repository, its input files named from
/// there, trimmed for `--quick` (the photos then come from `quick_photos`), its points'
/// PSFs on `backend` where its job takes one.
///
/// # Errors
/// An unreadable or invalid spec, a quick plan that names values the spec lacks, photos that
/// cannot be read or written.
pub fn prepared_spec(
    root: &Path,
    id: ResultId,
    part: &Part,
    quick: Option<&Path>,
    backend: Backend,
) -> Result<SweepSpec> {
    let path = root.join(SPEC_DIR).join(part.file);
    let spec = load_spec(&path)?;
    // Paths stay as written when the run starts in the repository: the table's columns and the
    // hashes are then those of `udc-studio sweep presets/reproduce/…` run there.
    let here = std::env::current_dir().ok();
    let same = here
        .as_deref()
        .and_then(|h| h.canonicalize().ok())
        .zip(root.canonicalize().ok())
        .is_some_and(|(a, b)| a == b);
    let mut spec = if same {
        spec
    } else {
        crate::sweep::inputs_under(&spec, root)
    };
    if let Some(dir) = quick {
        quicken(&mut spec, part, dir)
            .with_context(|| format!("{} ({}), quick plan", id.as_str(), part.file))?;
        spec.name = format!("{} (quick)", spec.name);
    }
    let spec = spec.computed_on(backend);
    spec.validate()?;
    Ok(spec)
}

/// Applies a part's quick plan: the kept axis values, the base overrides, and small copies of
/// the photos it names.
fn quicken(spec: &mut SweepSpec, part: &Part, photo_dir: &Path) -> Result<()> {
    let plan = &part.quick;
    trim(spec, plan)?;
    if let Some(photo_param) = part.inputs.filter(|_| !plan.photos.is_empty()) {
        let Some(axis) = spec.axes.iter_mut().find(|a| a.param == photo_param) else {
            bail!("the spec has no photo axis `{photo_param}`");
        };
        let photos: Vec<String> = axis
            .values
            .iter()
            .flatten()
            .filter_map(|v| match v {
                ParamValue::Text(t) => Some(t.clone()),
                _ => None,
            })
            .collect();
        let picked = pick_photos(&photos, plan.photos);
        if picked.is_empty() {
            bail!("the photo axis `{photo_param}` lists no photos");
        }
        let mut small = Vec::new();
        for p in picked {
            small.push(ParamValue::Text(small_copy(Path::new(&p), photo_dir)?));
        }
        axis.values = Some(small);
    }
    Ok(())
}

/// Cuts the axes a plan names to the values it keeps and sets its base parameters. A value set
/// holds everywhere: an axis that linked its own values to that parameter no longer does.
fn trim(spec: &mut SweepSpec, plan: &QuickPlan) -> Result<()> {
    for (param, keep) in plan.keep {
        let Some(axis) = spec.axes.iter_mut().find(|a| a.param == *param) else {
            bail!("the spec has no axis `{param}`");
        };
        let values = udc_core::sweep::spec::axis_values(axis)
            .map_err(|(f, m)| anyhow!("axis `{param}`{f}: {m}"))?;
        let kept: Vec<usize> = (0..values.len())
            .filter(|k| keep.contains(&values[*k].to_arg().as_str()))
            .collect();
        if kept.len() != keep.len() {
            bail!(
                "axis `{param}` keeps {} but has {}",
                keep.join(", "),
                values
                    .iter()
                    .map(ParamValue::to_arg)
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
        axis.values = Some(kept.iter().map(|k| values[*k].clone()).collect());
        axis.range = None;
        axis.linspace = None;
        for linked in axis.with.values_mut() {
            *linked = kept
                .iter()
                .filter_map(|k| linked.get(*k).cloned())
                .collect();
        }
    }
    for (param, value) in plan.set {
        for axis in &mut spec.axes {
            axis.with.remove(*param);
        }
        spec.base.insert((*param).to_string(), value.to_param());
    }
    Ok(())
}

/// The photos whose file stems the plan names, in its order; the first ones when the spec lacks
/// them (another test set).
fn pick_photos(photos: &[String], wanted: &[&str]) -> Vec<String> {
    let stem = |p: &String| {
        Path::new(p)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let named: Vec<String> = wanted
        .iter()
        .filter_map(|w| photos.iter().find(|p| stem(p) == *w).cloned())
        .collect();
    if named.len() == wanted.len() {
        named
    } else {
        photos.iter().take(wanted.len()).cloned().collect()
    }
}

/// Writes `photo` scaled to at most [`QUICK_SIDE_PX`] on its longer side into `dir` (8-bit
/// PNG, the same bytes every time, so a second quick run resumes by hash); returns its path.
fn small_copy(photo: &Path, dir: &Path) -> Result<String> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let planes = udc_io::photo::load_photo(photo, Some(QUICK_SIDE_PX))?;
    let stem = photo
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "photo".into());
    let out = dir.join(format!("{stem}_{QUICK_SIDE_PX}.png"));
    let refs: Vec<&ndarray::Array2<f64>> = planes.iter().collect();
    udc_io::photo::write_photo_png(&out, &refs)?;
    Ok(out.to_string_lossy().into_owned())
}

/// The photos a prepared spec reads (the values of its photo axis), for the report.
pub fn photos_of(spec: &SweepSpec, photo_param: Option<&str>) -> Vec<String> {
    let Some(param) = photo_param else {
        return Vec::new();
    };
    spec.axes
        .iter()
        .filter(|a| a.param == param)
        .flat_map(|a| a.values.iter().flatten())
        .map(ParamValue::to_arg)
        .collect()
}
