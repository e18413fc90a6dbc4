//! Masks: OASIS reading, importing a mask back into cells, export options and layer maps.

use thiserror::Error;

use udc_core::ValueError;

/// What is wrong with an OASIS file (SEMI P39). A record's error says which record, at which
/// byte; a CBLOCK's records nest inside it.
#[derive(Debug, Error)]
pub enum OasisError {
    /// No `%SEMI-OASIS` magic.
    #[error("not an OASIS file (no %SEMI-OASIS header)")]
    NotOasis,
    /// A record that cannot be read.
    #[error("not a readable OASIS file: {0}")]
    Unreadable(Box<OasisError>),
    /// No END record: a truncated file.
    #[error("not a complete OASIS file: it has no END record")]
    NoEnd,
    /// Not exactly one cell that no other cell places.
    #[error("expected one top cell, found {} ({})", .found.len(), .found.join(", "))]
    TopCells {
        /// The unplaced cells.
        found: Vec<String>,
    },
    /// Placements nested deeper than 32 levels (a crafted or cyclic file).
    #[error("placements nest deeper than 32 levels")]
    TooDeep,
    /// A placement of a cell the file does not define.
    #[error("a placement of a missing cell `{name}`")]
    MissingCell {
        /// The cell's name (or `#n` for an unnamed reference number).
        name: String,
    },
    /// What is wrong inside one record.
    #[error("record {id} at byte {byte}: {error}")]
    Record {
        /// The record type.
        id: u64,
        /// Where it starts, in its (inflated) byte stream.
        byte: usize,
        /// What is wrong.
        error: Box<OasisError>,
    },
    /// The bytes end inside a record.
    #[error("the file ends inside a record (byte {byte})")]
    EndsInRecord {
        /// Where the next byte was expected.
        byte: usize,
    },
    /// A length beyond the address space.
    #[error("a length does not fit memory")]
    LengthTooLarge,
    /// A length that runs past the end of the bytes.
    #[error("a length of {bytes} bytes runs past the end")]
    PastEnd {
        /// The length.
        bytes: usize,
    },
    /// An unsigned integer of more than 64 bits.
    #[error("an integer overflows 64 bits")]
    Overflow64,
    /// A signed or tagged integer whose magnitude overflows.
    #[error("an integer overflows")]
    Overflow,
    /// A float real without its 4 or 8 bytes.
    #[error("short real")]
    ShortReal,
    /// A real of an unknown type.
    #[error("unknown real type {0}")]
    UnknownReal(u64),
    /// The bytes end inside a g-delta.
    #[error("the file ends inside a g-delta")]
    EndsInGDelta,
    /// An interval of an unknown type.
    #[error("unknown interval type {0}")]
    UnknownInterval(u64),
    /// More shapes and placements than an import expands.
    #[error("more than {max} shapes and placements to expand; import a smaller mask")]
    TooManyShapes {
        /// The most expanded.
        max: usize,
    },
    /// A hierarchy whose expansion would keep more than an import may hold.
    #[error(
        "its placements expand to more than {max_mib} MiB of polygons and cell instances; \
         import a smaller mask"
    )]
    ExpandsTooLarge {
        /// The most an import may keep, in MiB.
        max_mib: usize,
    },
    /// The END record does not end the file (or sits in a CBLOCK): the file is damaged.
    #[error("the file is damaged: its END record does not end the file")]
    EndNotLast,
    /// An END record's validation scheme other than none, CRC-32 or checksum-32.
    #[error("unknown validation scheme {0} in the END record")]
    UnknownValidation(u64),
    /// The END record's signature does not match the file's bytes: damaged or altered.
    #[error(
        "the file is damaged: its {scheme} validation signature is {stored:08x}, its bytes give \
         {computed:08x}"
    )]
    ValidationMismatch {
        /// `CRC-32` or `checksum-32`.
        scheme: &'static str,
        /// The signature in the file.
        stored: u32,
        /// The signature of the file's bytes.
        computed: u32,
    },
    /// A point list of an unknown type.
    #[error("unknown point-list type {0}")]
    UnknownPointList(u64),
    /// A repetition of an unknown type.
    #[error("unknown repetition type {0}")]
    UnknownRepetition(u64),
    /// An element outside any cell.
    #[error("an element comes before any CELL record")]
    ElementOutsideCell,
    /// A START record whose unit is not a positive number.
    #[error("the unit {unit} is not positive")]
    UnitNotPositive {
        /// The database units per micrometre.
        unit: f64,
    },
    /// A property value of an unknown type.
    #[error("unknown property value type {0}")]
    UnknownPropertyValue(u64),
    /// A CBLOCK compressed other than with deflate.
    #[error("unknown CBLOCK compression {0}")]
    UnknownCompression(u64),
    /// A CBLOCK that claims to inflate to more than is read.
    #[error("a CBLOCK of {bytes} bytes is too large")]
    CblockTooLarge {
        /// The inflated size it claims.
        bytes: u64,
    },
    /// A CBLOCK inside a CBLOCK (forbidden by SEMI P39).
    #[error("a CBLOCK inside a CBLOCK")]
    NestedCblock,
    /// A CBLOCK whose deflate stream is corrupt (the decoder's words).
    #[error("a CBLOCK does not inflate: {0}")]
    Inflate(std::io::Error),
    /// A record type SEMI P39 does not define.
    #[error("unknown record type {0}")]
    UnknownRecord(u64),
    /// A PLACEMENT with no cell, given or modal.
    #[error("a PLACEMENT names no cell")]
    PlacementWithoutCell,
    /// A TEXT with no string, given or modal.
    #[error("a TEXT has no string")]
    TextWithoutString,
    /// Paths, trapezoids or circles on the imported layer.
    #[error(
        "{kind} records on layer {layer}/{datatype} are not supported; convert them to polygons \
         (e.g. in KLayout) first"
    )]
    Unsupported {
        /// `PATH`, `TRAPEZOID` or `CIRCLE`.
        kind: &'static str,
        /// The imported layer.
        layer: u64,
        /// The imported datatype.
        datatype: u64,
    },
}

/// Why a mask cannot be read back into cells.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MaskImportError {
    /// The file's SHA-256 is not the one its export wrote beside it.
    #[error(
        "the file does not match its checksum in {} (SHA-256 {}… stated, {}… found): it was \
         changed or damaged after export; import it anyway with --ignore-checksum",
        .sidecar.display(), &.expected[..12], &.found[..12]
    )]
    ChecksumMismatch {
        /// The `.sha256` or `.manifest.json` that states the checksum.
        sidecar: std::path::PathBuf,
        /// The SHA-256 it states, hex.
        expected: String,
        /// The file's SHA-256, hex.
        found: String,
    },
    /// A `.sha256` or manifest beside the mask that states no SHA-256.
    #[error(
        "{} beside the mask states no SHA-256; import it anyway with --ignore-checksum",
        .sidecar.display()
    )]
    UnreadableChecksum {
        /// The sidecar.
        sidecar: std::path::PathBuf,
    },
    /// An extension that names no mask format this reader reads.
    #[error("cannot read `.{extension}` masks (expected .gds, .oas or .dxf)")]
    UnknownExtension {
        /// The extension, lower case, without the dot.
        extension: String,
    },
    /// A cell size that is not a positive number.
    #[error("the cell size must be positive (got {cell_um} µm)")]
    CellSize {
        /// The cell size, in µm.
        cell_um: f64,
    },
    /// Nothing drawn on the layer read.
    #[error("no polygon on layer {layer}/{datatype}")]
    NoPolygon {
        /// The layer.
        layer: i16,
        /// The datatype.
        datatype: i16,
    },
    /// A window of no cells, or of more than the import makes.
    #[error("the window of {cols}×{rows} cells is empty or larger than {max_cells} cells")]
    Window {
        /// Cells across.
        cols: usize,
        /// Cells down.
        rows: usize,
        /// The most cells an import makes.
        max_cells: usize,
    },
    /// A PNG without the `REGION=` note the export writes.
    #[error("the PNG states no REGION= note (not written by udc-studio)")]
    NoRegionNote,
    /// A `REGION=` note that does not name a region.
    #[error(transparent)]
    Region(#[from] ValueError),
    /// A PNG without a metric pixel size.
    #[error("the PNG has no metric pHYs chunk, so its pixel size is unknown")]
    NoPixelSize,
    /// A PNG too small to hold the axis pixel at its pixel size.
    #[error("the {width}×{height} image does not cover the axis pixel at {um_per_px} µm per pixel")]
    AxisPixelOutside {
        /// Image width in pixels.
        width: usize,
        /// Image height in pixels.
        height: usize,
        /// The image's pixel size, in µm.
        um_per_px: f64,
    },
}

/// A mask export option that cannot be used.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ExportOptionsError {
    /// A top cell name GDSII readers may refuse.
    #[error("top cell name `{name}`: use 1 to 32 letters, digits, `_`, `-` or `$`")]
    TopCellName {
        /// The name as given.
        name: String,
    },
    /// A layer or datatype outside GDSII's 0–255.
    #[error("{option} must be between 0 and 255 (got {value:?})")]
    OutOfRange {
        /// `layer`, `datatype` or `note layer`.
        option: &'static str,
        /// The value as given.
        value: i16,
    },
    /// Notes on the drawing layer would be drawn as openings.
    #[error("the note layer ({layer}) must differ from the drawing layer")]
    NoteLayerIsDrawingLayer {
        /// The layer both name.
        layer: i16,
    },
    /// A die frame that cannot be drawn (the core's words, naming the setting).
    #[error(transparent)]
    Frame(#[from] udc_core::mask::FrameError),
    /// A layer map entry that names no role.
    #[error("layer map: unknown role `{name}` (expected one of {})", .roles.join(", "))]
    UnknownRole {
        /// The entry's name.
        name: String,
        /// The roles a layer map names.
        roles: Vec<&'static str>,
    },
    /// A layer map that puts the openings on another written role's layer/datatype, where a
    /// mask house could not tell them apart.
    #[error(
        "layer map: the openings ({layer}/{datatype}) must be on their own layer/datatype (the \
         {role} layer is the same)"
    )]
    SharedLayer {
        /// The openings' layer.
        layer: i16,
        /// The openings' datatype.
        datatype: i16,
        /// The role on the same layer/datatype.
        role: &'static str,
    },
    /// A PNG resolution that is not a positive number.
    #[error("µm per pixel must be a positive number (got {um_per_px:?})")]
    UmPerPx {
        /// The resolution as given, in µm per pixel.
        um_per_px: f64,
    },
}

/// What is wrong with a layer map (the text format or a KLayout `.lyp`).
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum LayerMapError {
    /// A text line that is not `name layer/datatype`.
    #[error(
        "layer map line {line}: `{text}`: expected `name layer/datatype` (e.g. `openings 1/0`)"
    )]
    Line {
        /// The line (1-based).
        line: usize,
        /// The line as written, trimmed.
        text: String,
    },
    /// A `.lyp` source that is not `L/D@…`.
    #[error("layer map (.lyp): source `{found}` is not `L/D@…`")]
    LypSource {
        /// The source as written.
        found: String,
    },
    /// A `.lyp` layer without a name.
    #[error("layer map (.lyp): layer {layer}/{datatype} has no name")]
    LypUnnamed {
        /// The layer.
        layer: i16,
        /// The datatype.
        datatype: i16,
    },
}
