//! What a mask house needs beside a mask file: GDSII record limits, fixed timestamps, cell
//! names that do not clash when two exports are merged, the layer map (`<out>.layers.txt`),
//! the checksum (`<out>.sha256`) and the manifest (`<out>.manifest.json`).

use std::path::{Path, PathBuf};

use gds21::{GdsDateTime, GdsPath, GdsPoint};
use sha2::{Digest, Sha256};

use super::IoError;
use super::error::LayerMapError;
use super::safe_file::write_atomic;

/// Most points one GDSII XY record carries. The record length is 16 bits, and many readers
/// take it as signed, so a record stays within 32,767 bytes: 4 header bytes + 4095 × 8.
pub const MAX_XY_POINTS: usize = 4095;

/// Most vertices of one GDSII boundary: its XY record repeats the first point at the end.
pub const MAX_BOUNDARY_VERTICES: usize = MAX_XY_POINTS - 1;

/// Longest cell name this tool derives: 24 characters leave room for the `_MX_R270`-style
/// suffixes of the sub-cells within GDSII's 32.
pub const MAX_DERIVED_CELL_CHARS: usize = 24;

/// Width of outlines written as GDSII paths, in nm (1 µm: visible, and far below any feature
/// that matters on the note layer).
pub const OUTLINE_WIDTH_NM: i32 = 1000;

/// The GDSII modification/access time: 2000-01-01 00:00:00 for a deterministic export (two
/// identical exports are byte-identical), the current time otherwise.
pub fn gds_date(deterministic: bool) -> GdsDateTime {
    if deterministic {
        GdsDateTime {
            year: 100,
            month: 1,
            day: 1,
            hour: 0,
            minute: 0,
            second: 0,
        }
    } else {
        GdsDateTime::now()
    }
}

/// The lower-case hex SHA-256 of `bytes`.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// A GDS-legal cell name from a design name and its hash: the name's letters, digits and `_`
/// (anything else becomes `_`, upper case, at most 15 characters; `UDC` when nothing is left),
/// then `_` and the first 8 hex digits of the hash. Two designs get different names, so their
/// exports merge into one library without a clash.
pub fn derived_cell_name(design_name: &str, hash_hex: &str) -> String {
    let mut base: String = design_name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_uppercase()
            } else {
                '_'
            }
        })
        .collect();
    base = base.trim_matches('_').chars().take(15).collect();
    if base.is_empty() {
        base = "UDC".into();
    }
    let short: String = hash_hex.chars().take(8).collect::<String>().to_uppercase();
    format!("{base}_{short}")
}

/// An outline (closed ring of points, nm) as GDSII paths of `width_nm`, split so no XY record
/// holds more than [`MAX_XY_POINTS`] points; consecutive paths share their end point.
/// Extended ends (path type 2) cover the joins.
pub fn outline_paths(ring: &[GdsPoint], layer: i16, datatype: i16, width_nm: i32) -> Vec<GdsPath> {
    let Some(first) = ring.first() else {
        return Vec::new();
    };
    let mut closed = ring.to_vec();
    closed.push(first.clone());
    let mut out = Vec::new();
    let mut start = 0;
    while start + 1 < closed.len() {
        let end = (start + MAX_XY_POINTS).min(closed.len());
        out.push(GdsPath {
            layer,
            datatype,
            xy: closed[start..end].to_vec(),
            width: Some(width_nm),
            path_type: Some(2),
            ..Default::default()
        });
        start = end - 1;
    }
    out
}

/// One line of a layer map: a role or level name and its GDSII layer/datatype.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LayerEntry {
    /// What the layer holds (`openings`, `outline`, `notes`, `level_3`, …).
    pub name: String,
    /// GDSII layer (0–255).
    pub layer: i16,
    /// GDSII datatype (0–255).
    pub datatype: i16,
}

/// A layer map: names to GDSII layer/datatype pairs.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct LayerMap {
    /// The entries, in file order.
    pub entries: Vec<LayerEntry>,
}

impl LayerMap {
    /// Parses the text format (one `name layer/datatype` per line, `#` starts a comment) or a
    /// KLayout `.lyp` file (its `<name>` and `<source>layer/datatype@…</source>` per
    /// `<properties>`).
    ///
    /// # Errors
    /// A [`LayerMapError`] naming the line (or entry) that does not parse.
    pub fn parse(text: &str) -> Result<LayerMap, LayerMapError> {
        if text.trim_start().starts_with('<') {
            return Self::parse_lyp(text);
        }
        let mut entries = Vec::new();
        for (k, raw) in text.lines().enumerate() {
            let line = raw.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let bad = || LayerMapError::Line {
                line: k + 1,
                text: raw.trim().to_string(),
            };
            let mut words = line.split_whitespace();
            let (Some(name), Some(spec), None) = (words.next(), words.next(), words.next()) else {
                return Err(bad());
            };
            let (layer, datatype) = parse_pair(spec).ok_or_else(bad)?;
            entries.push(LayerEntry {
                name: name.to_string(),
                layer,
                datatype,
            });
        }
        Ok(LayerMap { entries })
    }

    /// KLayout's layer properties: each `<properties>` names a layer by `<name>` and sources
    /// it as `<source>L/D@1</source>`.
    fn parse_lyp(text: &str) -> Result<LayerMap, LayerMapError> {
        let tag = |block: &str, t: &str| -> Option<String> {
            let open = format!("<{t}>");
            let a = block.find(&open)? + open.len();
            let b = block[a..].find(&format!("</{t}>"))? + a;
            Some(block[a..b].trim().to_string())
        };
        let mut entries = Vec::new();
        for block in text.split("<properties>").skip(1) {
            let source = tag(block, "source").unwrap_or_default();
            let spec = source.split('@').next().unwrap_or("").trim();
            let (layer, datatype) = parse_pair(spec).ok_or_else(|| LayerMapError::LypSource {
                found: source.clone(),
            })?;
            let name = tag(block, "name")
                .filter(|n| !n.is_empty())
                .ok_or(LayerMapError::LypUnnamed { layer, datatype })?;
            // A `.lyp` name may say more than the role ("openings (clear)"): the first word.
            let name = name.split_whitespace().next().unwrap_or("").to_string();
            entries.push(LayerEntry {
                name,
                layer,
                datatype,
            });
        }
        Ok(LayerMap { entries })
    }

    /// The layer/datatype named `name`.
    pub fn get(&self, name: &str) -> Option<(i16, i16)> {
        self.entries
            .iter()
            .find(|e| e.name == name)
            .map(|e| (e.layer, e.datatype))
    }

    /// The map in the text format [`LayerMap::parse`] reads, after `#` header lines.
    pub fn to_text(&self, header: &[String]) -> String {
        let mut s: String = header.iter().map(|h| format!("# {h}\n")).collect();
        for e in &self.entries {
            s.push_str(&format!("{} {}/{}\n", e.name, e.layer, e.datatype));
        }
        s
    }

    /// The map as JSON: `[{"name", "layer", "datatype"}, …]`.
    pub fn to_json(&self) -> serde_json::Value {
        self.entries
            .iter()
            .map(|e| serde_json::json!({"name": e.name, "layer": e.layer, "datatype": e.datatype}))
            .collect()
    }
}

/// `L/D` with both in 0–255.
fn parse_pair(spec: &str) -> Option<(i16, i16)> {
    let (l, d) = spec.split_once('/')?;
    let l: i16 = l.trim().parse().ok()?;
    let d: i16 = d.trim().parse().ok()?;
    ((0..=255).contains(&l) && (0..=255).contains(&d)).then_some((l, d))
}

/// `<path><suffix>` (e.g. `mask.gds.sha256`).
pub fn beside(path: &Path, suffix: &str) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(suffix);
    path.with_file_name(name)
}

/// The files written beside an export.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Sidecars {
    /// `<out>.sha256`: one `sha256sum`-compatible line.
    pub checksum: PathBuf,
    /// `<out>.manifest.json`.
    pub manifest: PathBuf,
    /// `<out>.layers.txt` (GDSII exports only).
    pub layers: Option<PathBuf>,
}

/// Writes `<path>.sha256` of the file at `path`, `<path>.layers.txt` when `layers` is given, and
/// `<path>.manifest.json`: `manifest` plus `file`, `sha256`, `tool`, `tool_version`, and
/// `layer_map` / `layer_map_file` when there is one.
///
/// # Errors
/// [`IoError::File`] when the file cannot be read back or a sidecar cannot be written.
pub fn write_sidecars(
    path: &Path,
    mut manifest: serde_json::Map<String, serde_json::Value>,
    layers: Option<(&LayerMap, &[String])>,
) -> Result<Sidecars, IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::file("read", path, e))?;
    let hash = sha256_hex(&bytes);
    let file_name = path
        .file_name()
        .unwrap_or_default()
        .to_string_lossy()
        .into_owned();
    let checksum = beside(path, ".sha256");
    // `sha256sum -c` format: hash, two spaces, the file name (relative, so the pair can move).
    write_atomic(&checksum, format!("{hash}  {file_name}\n").as_bytes())?;
    manifest.insert("file".into(), file_name.into());
    manifest.insert("sha256".into(), hash.into());
    manifest.insert("tool".into(), "udc-studio".into());
    manifest.insert("tool_version".into(), crate::TOOL_VERSION.into());
    let mut layers_path = None;
    if let Some((map, header)) = layers {
        let p = beside(path, ".layers.txt");
        write_atomic(&p, map.to_text(header).as_bytes())?;
        manifest.insert("layer_map".into(), map.to_json());
        manifest.insert(
            "layer_map_file".into(),
            p.file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned()
                .into(),
        );
        layers_path = Some(p);
    }
    let manifest_path = beside(path, ".manifest.json");
    let text = serde_json::to_string_pretty(&serde_json::Value::Object(manifest))
        .unwrap_or_else(|_| "{}".into());
    write_atomic(&manifest_path, text.as_bytes())?;
    Ok(Sidecars {
        checksum,
        manifest: manifest_path,
        layers: layers_path,
    })
}
