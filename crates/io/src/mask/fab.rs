//! The mask export's side of [`crate::fab`]: the roles of its layers, the names derived from
//! the design, and the manifest.

use std::path::Path;

use super::{ExportOptions, MaskFormat};
use crate::IoError;
use crate::design::file::to_json;
use crate::error::ExportOptionsError;
use crate::fab::{LayerEntry, LayerMap, Sidecars, derived_cell_name, sha256_hex, write_sidecars};
use udc_core::design::Design;

/// What a layer of a mask export holds (the names of a layer map file).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LayerRole {
    /// The drawn polygons (openings for the open tone, chrome for the chrome tone).
    Openings,
    /// The pupil outline (a path).
    Outline,
    /// The text notes.
    Notes,
    /// The die frame around the active area (default layer 10/0).
    Frame,
    /// The alignment crosses (default layer 11/0).
    Marks,
    /// The label: design name, date, scale (default layer 12/0).
    Label,
    /// The red emitters of the design's subpixel layer (default 21/0).
    EmitterRed,
    /// The green emitters (default 22/0).
    EmitterGreen,
    /// The blue emitters (default 23/0).
    EmitterBlue,
}

impl LayerRole {
    /// Every role, in layer-map order.
    pub const ALL: [LayerRole; 9] = [
        LayerRole::Openings,
        LayerRole::Outline,
        LayerRole::Notes,
        LayerRole::Frame,
        LayerRole::Marks,
        LayerRole::Label,
        LayerRole::EmitterRed,
        LayerRole::EmitterGreen,
        LayerRole::EmitterBlue,
    ];

    /// The emitter roles in R, G, B order (the subpixel layer's colour index).
    pub const EMITTERS: [LayerRole; 3] = [
        LayerRole::EmitterRed,
        LayerRole::EmitterGreen,
        LayerRole::EmitterBlue,
    ];

    /// The name in a layer map file.
    pub fn as_str(self) -> &'static str {
        match self {
            LayerRole::Openings => "openings",
            LayerRole::Outline => "outline",
            LayerRole::Notes => "notes",
            LayerRole::Frame => "frame",
            LayerRole::Marks => "marks",
            LayerRole::Label => "label",
            LayerRole::EmitterRed => "emitter_red",
            LayerRole::EmitterGreen => "emitter_green",
            LayerRole::EmitterBlue => "emitter_blue",
        }
    }
}

/// Default layer/datatype of the die frame: well above the drawing and note layers' defaults
/// (1 and 2), so a mask house can drop it from the write job by layer.
pub const FRAME_LAYER: (i16, i16) = (10, 0);
/// Default layer/datatype of the alignment marks.
pub const MARKS_LAYER: (i16, i16) = (11, 0);
/// Default layer/datatype of the label.
pub const LABEL_LAYER: (i16, i16) = (12, 0);
/// Default layer/datatype of the R, G, B emitters.
pub const EMITTER_LAYERS: [(i16, i16); 3] = [(21, 0), (22, 0), (23, 0)];

/// The layer/datatype of every role.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MaskLayers {
    /// Drawn polygons.
    pub openings: (i16, i16),
    /// Pupil outline.
    pub outline: (i16, i16),
    /// Text notes.
    pub notes: (i16, i16),
    /// Die frame.
    pub frame: (i16, i16),
    /// Alignment marks.
    pub marks: (i16, i16),
    /// Label.
    pub label: (i16, i16),
    /// R, G, B emitters.
    pub emitters: [(i16, i16); 3],
}

impl MaskLayers {
    /// The pair of `role`.
    pub fn of(&self, role: LayerRole) -> (i16, i16) {
        match role {
            LayerRole::Openings => self.openings,
            LayerRole::Outline => self.outline,
            LayerRole::Notes => self.notes,
            LayerRole::Frame => self.frame,
            LayerRole::Marks => self.marks,
            LayerRole::Label => self.label,
            LayerRole::EmitterRed => self.emitters[0],
            LayerRole::EmitterGreen => self.emitters[1],
            LayerRole::EmitterBlue => self.emitters[2],
        }
    }

    /// The pair of `role`, to set.
    fn of_mut(&mut self, role: LayerRole) -> &mut (i16, i16) {
        match role {
            LayerRole::Openings => &mut self.openings,
            LayerRole::Outline => &mut self.outline,
            LayerRole::Notes => &mut self.notes,
            LayerRole::Frame => &mut self.frame,
            LayerRole::Marks => &mut self.marks,
            LayerRole::Label => &mut self.label,
            LayerRole::EmitterRed => &mut self.emitters[0],
            LayerRole::EmitterGreen => &mut self.emitters[1],
            LayerRole::EmitterBlue => &mut self.emitters[2],
        }
    }

    /// The `roles` as a [`LayerMap`] (what `<out>.layers.txt` holds).
    pub fn to_map(&self, roles: &[LayerRole]) -> LayerMap {
        LayerMap {
            entries: roles
                .iter()
                .map(|&r| LayerEntry {
                    name: r.as_str().into(),
                    layer: self.of(r).0,
                    datatype: self.of(r).1,
                })
                .collect(),
        }
    }
}

impl ExportOptions {
    /// The layers of every role: the `--layer-map` entries, the rest from `layer`/`datatype`
    /// (openings), `note_layer` (outline and notes, datatype 0) and the frame's defaults
    /// ([`FRAME_LAYER`], [`MARKS_LAYER`], [`LABEL_LAYER`]).
    ///
    /// # Errors
    /// [`ExportOptionsError::UnknownRole`] for a map entry that names no role,
    /// [`ExportOptionsError::SharedLayer`] for a map that puts the openings on the
    /// layer/datatype of another role this export writes.
    pub fn mask_layers(&self) -> Result<MaskLayers, ExportOptionsError> {
        let mut l = MaskLayers {
            openings: (self.layer, self.datatype),
            outline: (self.note_layer, 0),
            notes: (self.note_layer, 0),
            frame: FRAME_LAYER,
            marks: MARKS_LAYER,
            label: LABEL_LAYER,
            emitters: EMITTER_LAYERS,
        };
        if let Some(map) = &self.layer_map {
            for e in &map.entries {
                let Some(role) = LayerRole::ALL.into_iter().find(|r| r.as_str() == e.name) else {
                    return Err(ExportOptionsError::UnknownRole {
                        name: e.name.clone(),
                        roles: LayerRole::ALL.iter().map(|r| r.as_str()).collect(),
                    });
                };
                *l.of_mut(role) = (e.layer, e.datatype);
            }
        }
        // Only the roles written can clash: a frame layer equal to `--layer` is harmless when
        // no frame is drawn, and refusing it would break exports that worked before frames.
        if let Some(r) = self
            .written_roles()
            .into_iter()
            .find(|&r| r != LayerRole::Openings && l.of(r) == l.openings)
        {
            return Err(ExportOptionsError::SharedLayer {
                layer: l.openings.0,
                datatype: l.openings.1,
                role: r.as_str(),
            });
        }
        Ok(l)
    }

    /// The roles this export writes, in layer-map order: openings, outline and notes always,
    /// frame, marks and label when asked for and the format draws them (PNG does not), the
    /// emitters when the design has a subpixel layer and the format has cells (GDSII, OASIS).
    pub fn written_roles(&self) -> Vec<LayerRole> {
        let f = &self.frame;
        let drawn = self.format != MaskFormat::Png;
        LayerRole::ALL
            .into_iter()
            .filter(|r| match r {
                LayerRole::Openings | LayerRole::Outline | LayerRole::Notes => true,
                LayerRole::Frame => drawn && f.frame,
                LayerRole::Marks => drawn && f.marks,
                LayerRole::Label => drawn && f.label,
                LayerRole::EmitterRed | LayerRole::EmitterGreen | LayerRole::EmitterBlue => {
                    self.emitters && matches!(self.format, MaskFormat::Gds | MaskFormat::Oas)
                }
            })
            .collect()
    }

    /// The options as written for `design`: the layer map applied to `layer`, `datatype` and
    /// `note_layer`, and the top cell named when none was given.
    ///
    /// # Errors
    /// As [`ExportOptions::mask_layers`], for a bad layer map.
    pub fn resolved(&self, design: &Design) -> Result<ExportOptions, ExportOptionsError> {
        let l = self.mask_layers()?;
        let mut o = self.clone();
        (o.layer, o.datatype) = l.openings;
        o.note_layer = l.notes.0;
        o.emitters = design.subpixels.is_some();
        if o.top_cell.is_none() {
            o.top_cell = Some(derived_cell_name(&design.name, &design_hash(design)));
        }
        Ok(o)
    }

    /// The layer of every role as written ("layers: openings 1/0, outline 5/0, notes 2/0"):
    /// a layer map can give the outline and the notes layers of their own.
    pub fn layers_line(&self) -> String {
        match self.mask_layers() {
            Ok(l) => {
                let roles: Vec<String> = self
                    .written_roles()
                    .into_iter()
                    .map(|r| {
                        let (layer, datatype) = l.of(r);
                        format!("{} {layer}/{datatype}", r.as_str())
                    })
                    .collect();
                format!("layers: {}", roles.join(", "))
            }
            // Export refuses a bad map before any report exists; the plain options then.
            Err(_) => format!(
                "layer {}/{}; notes and pupil outline on layer {}",
                self.layer, self.datatype, self.note_layer
            ),
        }
    }

    /// The top cell name (after [`ExportOptions::resolved`], always the derived or given one).
    pub fn top_cell_name(&self) -> &str {
        self.top_cell.as_deref().unwrap_or("UDC_MASK")
    }
}

/// The SHA-256 (hex) of the design's JSON: the same design always gives the same hash.
pub fn design_hash(design: &Design) -> String {
    sha256_hex(to_json(design).as_bytes())
}

/// Writes the checksum, the manifest and (GDSII) the layer map beside the export at `path`.
pub(super) fn write_mask_sidecars(
    design: &Design,
    o: &ExportOptions,
    path: &Path,
) -> Result<Sidecars, IoError> {
    let layers = o.mask_layers().map_err(|error| IoError::MaskOptions {
        path: path.to_path_buf(),
        error,
    })?;
    let map = layers.to_map(&o.written_roles());
    let spec = &o.spec;
    let mut m = serde_json::Map::new();
    m.insert("format".into(), o.format.as_str().into());
    m.insert(
        "design".into(),
        serde_json::json!({"name": design.name, "sha256": design_hash(design)}),
    );
    m.insert(
        "parameters".into(),
        serde_json::json!({
            "region": spec.region.label(),
            "tone": spec.tone.as_str(),
            "grid_nm": spec.grid_nm,
            "top_cell": o.top_cell_name(),
            "gds_cells": match o.gds_cells {
                super::GdsCells::Strans => "strans",
                super::GdsCells::PerOrientation => "per-orientation",
            },
            "um_per_px": o.um_per_px,
            "png_bits": match o.png_bits {
                super::PngBits::One => 1,
                super::PngBits::Eight => 8,
            },
            "deterministic": o.deterministic,
        }),
    );
    let f = &o.frame;
    if f.any() {
        // Only when asked for: the manifests of frameless exports stay as they were.
        m.insert(
            "frame".into(),
            serde_json::json!({
                "frame": f.frame,
                "marks": f.marks,
                "label": f.label,
                "drawn": o.format != MaskFormat::Png,
                "margin_um": f.margin_um,
                "frame_width_um": f.frame_width_um,
                "mark_size_um": f.mark_size_um,
                "mark_arm_width_um": f.mark_arm_width_um,
                "label_height_um": f.label_height_um,
            }),
        );
    }
    let header = vec![
        format!(
            "layer map of {}",
            path.file_name().unwrap_or_default().to_string_lossy()
        ),
        "one `name layer/datatype` per line; udc-studio export --layer-map reads this format"
            .into(),
        format!("tone {}: {}", spec.tone.as_str(), spec.tone.meaning()),
    ];
    if matches!(o.format, MaskFormat::Gds | MaskFormat::Oas) {
        write_sidecars(path, m, Some((&map, &header)))
    } else {
        m.insert("layer_map".into(), map.to_json());
        write_sidecars(path, m, None)
    }
}
