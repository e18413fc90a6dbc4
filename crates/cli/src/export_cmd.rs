//! `udc-studio export`: a photolithography mask of a design (GDSII, OASIS, DXF, SVG or PNG) and the
//! files a mask house gets beside it.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use super::DesignSelection;
use super::drc::{Checked, RuleArgs, report_lines, strict_error};
use udc_core::Progress;
use udc_core::mask::{BorderPolicy, FrameSpec, MaskRegion, MaskSpec, Tone};
use udc_io::IoError;
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
    /// What happens to an opening the region's edge cuts: `margin` (left out; with chrome
    /// drawn, the region framed in chrome), `drop` (left out), `extend` (drawn whole past the
    /// edge; open tone) or `cut` (cut at the edge, as a pixel cell the fab arrays needs).
    #[arg(long, default_value = "margin")]
    pub border: BorderPolicy,
    /// Width of the chrome frame `--border margin` draws around a chrome-drawn region, µm (at
    /// least one grid step, at most 10 000).
    #[arg(long, default_value_t = udc_core::mask::border::DEFAULT_MARGIN_UM, allow_negative_numbers = true)]
    pub margin_um: f64,
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
    /// Refuse to write the mask when its written geometry breaks a design rule (else they are
    /// warnings).
    #[arg(long)]
    pub strict: bool,
    /// Also write a KLayout DRC deck (`.lydrc`) with these rules, so a fab runs the checks
    /// this export ran.
    #[arg(long)]
    pub write_drc_deck: Option<PathBuf>,
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
    let rules = args.rules.resolve()?;
    let options = ExportOptions {
        format: args.format,
        spec: MaskSpec {
            region: args.region,
            tone: args.tone,
            grid_nm: args.grid_nm,
            border: args.border,
            margin_um: args.margin_um,
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
        rules,
        strict: args.strict,
    };
    udc_io::safe_file::check_not_an_input(&args.out, &args.selection.input_files())?;
    if let Some(deck) = &args.write_drc_deck {
        udc_io::safe_file::check_not_an_input(deck, &args.selection.input_files())?;
    }
    let report = match export_mask(&design, &options, &args.out, &Progress::new()) {
        Ok(r) => r,
        Err(IoError::RulesBroken { report, scope }) => {
            println!("{scope}");
            for line in report_lines(&report, Checked::Display) {
                println!("{line}");
            }
            return Err(strict_error(&report));
        }
        Err(e) => return Err(e.into()),
    };
    for line in report.lines() {
        println!("{line}");
    }
    let drc = &report.drc;
    if drc.report.is_clean() {
        println!("{}: no violation", drc.scope_line());
    } else {
        println!(
            "warning: {} design-rule violations (--strict refuses them); {}:",
            drc.report.total(),
            drc.scope_line()
        );
        for line in report_lines(&drc.report, Checked::Display) {
            println!("warning: {line}");
        }
    }
    if let Some(deck) = &args.write_drc_deck {
        let layers = report.options.mask_layers()?;
        let text = udc_io::mask::drc_deck(&rules, layers.openings, args.tone, &design.name);
        udc_io::safe_file::write_atomic(deck, text.as_bytes())?;
        println!("DRC deck: {}", deck.display());
    }
    Ok(())
}

/// Reads a `--layer-map` file (a small text file).
fn read_layer_map(path: &std::path::Path) -> Result<udc_io::fab::LayerMap> {
    let bytes = udc_io::safe_file::read_bounded(path, 1 << 20, "read the layer map")?;
    let text = String::from_utf8_lossy(&bytes);
    udc_io::fab::LayerMap::parse(&text).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
}
