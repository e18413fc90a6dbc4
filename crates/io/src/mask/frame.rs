//! The die frame, alignment marks and label of an export, on their layers: what every writer
//! (and a new one, such as OASIS) draws beside the region. The geometry is
//! [`udc_core::mask::frame_geometry`]'s; this adds the layer roles and the label's text.

use super::{ExportOptions, LayerRole, MaskFormat, region_bbox_nm};
use crate::fab::gds_date;
use udc_core::mask::{
    FrameLabel, FramePart, MaskError, MaskLayout, Polygon, frame_geometry, label_text,
};

/// The frame, marks and label of one export.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FrameDrawing {
    /// Polygons (nm, y up, on the layout's grid) and the role whose layer they go on
    /// ([`LayerRole::Frame`] or [`LayerRole::Marks`]).
    pub polygons: Vec<(LayerRole, Polygon)>,
    /// The label, on [`LayerRole::Label`], when asked for.
    pub label: Option<FrameLabel>,
    /// `[min x, min y, max x, max y]` of the region and everything above, nm (the label's
    /// anchor, not its letters: their width depends on the reader's font).
    pub extent_nm: [i64; 4],
}

/// The label's date: the GDSII file's own date, so a deterministic export (2000-01-01) stays
/// byte-identical and a GDSII label never disagrees with its library's timestamp.
pub fn label_date(deterministic: bool) -> String {
    let d = gds_date(deterministic);
    format!(
        "{:04}-{:02}-{:02}",
        1900 + i32::from(d.year),
        d.month,
        d.day
    )
}

/// The frame, marks and label `o.frame` asks for around `layout`'s region, labelled with
/// `design_name`; empty for PNG (a raster of the active area only).
///
/// # Errors
/// As [`frame_geometry`]: bad sizes, or a frame beyond GDSII's coordinates.
pub fn frame_drawing(
    layout: &MaskLayout,
    o: &ExportOptions,
    design_name: &str,
) -> Result<FrameDrawing, MaskError> {
    let bbox = region_bbox_nm(layout);
    if o.format == MaskFormat::Png || !o.frame.any() {
        return Ok(FrameDrawing {
            extent_nm: bbox,
            ..FrameDrawing::default()
        });
    }
    let text = label_text(design_name, &label_date(o.deterministic), layout.grid_nm);
    let g = frame_geometry(&o.frame, bbox, layout.grid_nm, &text)?;
    Ok(FrameDrawing {
        polygons: g
            .polygons
            .into_iter()
            .map(|(part, p)| {
                let role = match part {
                    FramePart::Frame => LayerRole::Frame,
                    FramePart::Marks => LayerRole::Marks,
                };
                (role, p)
            })
            .collect(),
        label: g.label,
        extent_nm: g.extent_nm,
    })
}

/// The report's line about the frame, when one was asked for.
pub(super) fn report_line(o: &ExportOptions) -> Option<String> {
    let f = &o.frame;
    if !f.any() {
        return None;
    }
    let parts: Vec<&str> = [(f.frame, "frame"), (f.marks, "marks"), (f.label, "label")]
        .into_iter()
        .filter_map(|(on, name)| on.then_some(name))
        .collect();
    if o.format == MaskFormat::Png {
        return Some(format!(
            "{}: not drawn (a PNG holds the active area only)",
            parts.join(", ")
        ));
    }
    let layers = o.mask_layers().ok()?;
    let on: Vec<String> = o
        .written_roles()
        .into_iter()
        .filter(|r| matches!(r, LayerRole::Frame | LayerRole::Marks | LayerRole::Label))
        .map(|r| {
            let (l, d) = layers.of(r);
            format!("{} on {l}/{d}", r.as_str())
        })
        .collect();
    Some(format!(
        "{} ({} µm outside the region); {}",
        parts.join(", "),
        f.margin_um,
        on.join(", ")
    ))
}
