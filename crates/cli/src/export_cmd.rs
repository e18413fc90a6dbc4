//! `udc-studio export`: a photolithography mask of a design (GDSII, OASIS, DXF, SVG or PNG) and the
//! files a mask house gets beside it.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use super::DesignSelection;
use super::drc::{Checked, RuleArgs, report_lines, strict_error};
use udc_core::Progress;
use udc_core::mask::{FrameSpec, MaskRegion, MaskSpec, Tone};
use udc_io::mask::{ExportOptions, GdsCells, MaskFormat, PngBits, export_mask};

/// Arguments of `udc-studio export`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The design to write as a mask.
    #[command(flatten)]
    pub selection: DesignSelection,
    /// File format: gds, oas (OASIS), dxf, svg or png.
    #[arg(long)]
    pub format: MaskFormat,
    /// Which pixels: `pixel` (the one on the optical axis), `pupil` (every pixel over the lens
    /// pupil, with its outline) or `WxH` (a block of pixels centred on the axis, e.g. 1080x2400).
    #[arg(long)]
    pub region: MaskRegion,
    /// What the polygons are: `open` (drawn = clear) or `chrome` (drawn = dark, gap included).
    #[arg(long, default_value = "open")]
    pub tone: Tone,
    /// Output file; the design is written beside it as `<FILE>.design.json`.
    #[arg(long)]
    pub out: PathBuf,
    /// GDSII layer of the drawn polygons.
    #[arg(long, default_value_t = 1)]
    pub layer: i16,
    /// GDSII datatype of the drawn polygons.
    #[arg(long, default_value_t = 0)]
    pub datatype: i16,
    /// Layer of the pupil outline and the text notes.
    #[arg(long, default_value_t = 2)]
    pub note_layer: i16,
    /// Coordinate grid in nm (the database unit is 1 nm).
    #[arg(long, default_value_t = 1)]
    pub grid_nm: u32,
    /// GDSII top cell name (default: the design's name and a short hash of the design).
    #[arg(long)]
    pub top_cell: Option<String>,
    /// Layer map file: one `role layer/datatype` per line (roles openings, outline, notes,
    /// frame, marks, label), or a KLayout `.lyp`; overrides --layer, --datatype and
    /// --note-layer.
    #[arg(long)]
    pub layer_map: Option<PathBuf>,
    /// Fixed timestamps (2000-01-01 00:00:00): identical exports are byte-identical.
    #[arg(long)]
    pub deterministic: bool,
    /// GDSII orientations: `strans` (one cell, reflected/rotated references) or
    /// `per-orientation` (one cell per orientation, plain references).
    #[arg(long, default_value = "strans")]
    pub gds_cells: GdsCells,
    /// PNG pixel size in µm.
    #[arg(long, default_value_t = 1.0)]
    pub um_per_px: f64,
    /// PNG bits per pixel: 1 (black/white) or 8 (grey = covered fraction).
    #[arg(long, default_value = "8")]
    pub png_bits: PngBits,
    /// The design rules checked before writing (as `udc-studio drc`).
    #[command(flatten)]
    pub rules: RuleArgs,
    /// Refuse to write the mask when it breaks a design rule (else they are warnings).
    #[arg(long)]
    pub strict: bool,
    /// Draw a die frame around the region, on layer `frame` (default 10/0; not in PNG).
    #[arg(long)]
    pub frame: bool,
    /// Draw four alignment crosses beyond the frame's corners, on layer `marks` (default 11/0).
    #[arg(long)]
    pub marks: bool,
    /// Write a label (design name, date, scale) below the region, on layer `label` (default
    /// 12/0); the date is 2000-01-01 with --deterministic.
    #[arg(long)]
    pub label: bool,
    /// Gap between the region and the frame, the frame and the marks, the marks and the
    /// label, in µm [default: 50].
    #[arg(long, allow_negative_numbers = true)]
    pub frame_margin_um: Option<f64>,
    /// Width of the frame in µm [default: 10].
    #[arg(long, allow_negative_numbers = true)]
    pub frame_width_um: Option<f64>,
    /// Side of an alignment cross in µm [default: 100].
    #[arg(long, allow_negative_numbers = true)]
    pub mark_size_um: Option<f64>,
    /// Width of an alignment cross's arms in µm [default: 10].
    #[arg(long, allow_negative_numbers = true)]
    pub mark_arm_width_um: Option<f64>,
    /// Height of the label's letters in µm (DXF, SVG) [default: 20].
    #[arg(long, allow_negative_numbers = true)]
    pub label_height_um: Option<f64>,
}

impl ExportArgs {
    /// The frame options, unset sizes at their defaults.
    fn frame(&self) -> FrameSpec {
        let d = FrameSpec::default();
        FrameSpec {
            frame: self.frame,
            marks: self.marks,
            label: self.label,
            margin_um: self.frame_margin_um.unwrap_or(d.margin_um),
            frame_width_um: self.frame_width_um.unwrap_or(d.frame_width_um),
            mark_size_um: self.mark_size_um.unwrap_or(d.mark_size_um),
            mark_arm_width_um: self.mark_arm_width_um.unwrap_or(d.mark_arm_width_um),
            label_height_um: self.label_height_um.unwrap_or(d.label_height_um),
        }
    }
}

/// Runs `udc-studio export`.
pub(super) fn export_cmd(args: &ExportArgs) -> Result<()> {
    let design = args.selection.resolve()?;
    // Checked first: a strict export that fails leaves nothing behind.
    let drc = udc_core::mask::drc::check(&design, &args.rules.resolve()?);
    if args.strict && !drc.is_clean() {
        for line in report_lines(&drc, Checked::Display) {
            println!("{line}");
        }
        return Err(strict_error(&drc));
    }
    let options = ExportOptions {
        format: args.format,
        spec: MaskSpec {
            region: args.region,
            tone: args.tone,
            grid_nm: args.grid_nm,
            ..MaskSpec::default()
        },
        layer: args.layer,
        datatype: args.datatype,
        note_layer: args.note_layer,
        top_cell: args.top_cell.clone(),
        gds_cells: args.gds_cells,
        um_per_px: args.um_per_px,
        png_bits: args.png_bits,
        layer_map: args.layer_map.as_deref().map(read_layer_map).transpose()?,
        deterministic: args.deterministic,
        frame: args.frame(),
        // Set from the design when the export resolves its options.
        emitters: false,
    };
    udc_io::safe_file::check_not_an_input(&args.out, &args.selection.input_files())?;
    let report = export_mask(&design, &options, &args.out, &Progress::new())?;
    for line in report.lines() {
        println!("{line}");
    }
    if !drc.is_clean() {
        println!(
            "warning: {} design-rule violations (--strict refuses them):",
            drc.total()
        );
        for line in report_lines(&drc, Checked::Display) {
            println!("warning: {line}");
        }
    }
    Ok(())
}

/// Reads a `--layer-map` file (a small text file).
fn read_layer_map(path: &std::path::Path) -> Result<udc_io::fab::LayerMap> {
    let bytes = udc_io::safe_file::read_bounded(path, 1 << 20, "read the layer map")?;
    let text = String::from_utf8_lossy(&bytes);
    udc_io::fab::LayerMap::parse(&text).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
}
