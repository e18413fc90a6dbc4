//! Tables: a spectral response read, a sweep's results table, `mtf.csv`.

use thiserror::Error;

use udc_core::design::MAX_WAVELENGTHS;

/// What is wrong with a table: a spectral response read, a sweep's results table read or
/// written (CSV journal and Parquet), or `mtf.csv` written.
#[derive(Debug, Error)]
pub enum TableError {
    /// A spectral response table that does not parse, or channels it cannot give.
    #[error(transparent)]
    Spectral(#[from] SpectralError),
    /// A `--spectral-step-nm` that cannot sample the spectral table; the message names the
    /// flag, since the step is not in the file.
    #[error("--spectral-step-nm: {0}")]
    SpectralStep(SpectralError),
    /// An analysis without channels has no MTF columns to write.
    #[error("the analysis has no channel")]
    NoChannel,
    /// Channels whose MTFs have different numbers of rings cannot share the frequency column.
    #[error("channel {channel}'s MTF does not have {rings} rings like channel {first}'s")]
    MtfRings {
        /// The channel whose MTF differs.
        channel: String,
        /// The number of rings of the first channel's MTF.
        rings: usize,
        /// The first channel.
        first: String,
    },
    /// A results row with more or fewer fields than the header.
    #[error("line {line}: {found} fields where the header has {expected}")]
    FieldCount {
        /// The line of the row (1-based, the header is line 1).
        line: usize,
        /// Fields in the row.
        found: usize,
        /// Columns of the header.
        expected: usize,
    },
    /// A results row whose `point` field is not a point index.
    #[error("line {line}: `{value}` is not a point index")]
    PointIndex {
        /// The line of the row (1-based).
        line: usize,
        /// The field as written.
        value: String,
    },
    /// A results row whose metric field is neither empty nor a number.
    #[error("line {line}: `{value}` is not a number ({metric})")]
    Metric {
        /// The line of the row (1-based).
        line: usize,
        /// The field as written.
        value: String,
        /// The metric's column.
        metric: String,
    },
    /// A results table whose header is not the sweep's.
    #[error(
        "its columns ({}) are not this sweep's ({}); write to a new --out folder",
        .found.join(","),
        .expected.join(",")
    )]
    Columns {
        /// The table's header.
        found: Vec<String>,
        /// The sweep's columns.
        expected: Vec<String>,
    },
    /// The CSV reader or writer failed (its own words: a malformed record, a write error).
    #[error("{0}")]
    Csv(csv::Error),
    /// The Parquet writer failed (its own words).
    #[error("Parquet: {0}")]
    Parquet(parquet::errors::ParquetError),
    /// Arrow refused a record batch of the Parquet table (its own words).
    #[error("Parquet: {0}")]
    Arrow(arrow_schema::ArrowError),
    /// An integer axis value that is not a whole number, met writing the Parquet column.
    #[error("Parquet: {column}: `{value}` is not a whole number")]
    NotWholeNumber {
        /// The axis column.
        column: String,
        /// The value as the command line spells it.
        value: String,
    },
    /// A float axis value that is not a number, met writing the Parquet column.
    #[error("Parquet: {column}: `{value}` is not a number")]
    NotNumber {
        /// The axis column.
        column: String,
        /// The value as the command line spells it.
        value: String,
    },
    /// A plot that names a column the results table does not have.
    #[error(
        "plot `{plot}`: no column `{column}` (axes: {}; metrics: {})",
        .axes.join(", "),
        .metrics.join(", ")
    )]
    MissingColumn {
        /// The plot's file stem.
        plot: String,
        /// The column asked for.
        column: String,
        /// The table's axis columns.
        axes: Vec<String>,
        /// The table's metric columns.
        metrics: Vec<String>,
    },
}

/// What is wrong with a sensor spectral response table (CSV), or with sampling it: lines and
/// columns are 1-based, as an editor shows them.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SpectralError {
    /// A line without the four columns `wavelength_nm, r, g, b`.
    #[error("line {line}: expected 4 columns (wavelength_nm, r, g, b), found {found}")]
    ColumnCount {
        /// The line.
        line: usize,
        /// Columns found.
        found: usize,
    },
    /// A header whose first column does not name the wavelength.
    #[error(
        "line {line}: column 1: header `{found}` should name the wavelength (e.g. `wavelength_nm`)"
    )]
    WavelengthHeader {
        /// The line.
        line: usize,
        /// The first column's name as written.
        found: String,
    },
    /// A header without one of the `r`, `g`, `b` columns.
    #[error("line {line}: header has no `{channel}` column (expected wavelength_nm,r,g,b)")]
    MissingChannel {
        /// The line.
        line: usize,
        /// `r`, `g` or `b`.
        channel: &'static str,
    },
    /// A header that names one of the `r`, `g`, `b` columns twice.
    #[error("line {line}: header names the `{channel}` column twice")]
    DuplicateChannel {
        /// The line.
        line: usize,
        /// `r`, `g` or `b`.
        channel: &'static str,
    },
    /// A cell that is not a number.
    #[error("line {line}, column {column}: `{value}` is not a number")]
    NotANumber {
        /// The line.
        line: usize,
        /// The column.
        column: usize,
        /// The cell as written.
        value: String,
    },
    /// A cell that is NaN or infinite.
    #[error("line {line}, column {column}: `{value}` is not a finite number")]
    NotFinite {
        /// The line.
        line: usize,
        /// The column.
        column: usize,
        /// The cell as written.
        value: String,
    },
    /// A negative response or wavelength.
    #[error(
        "line {line}, column {column}: `{value}` is negative; responses and wavelengths are ≥ 0"
    )]
    Negative {
        /// The line.
        line: usize,
        /// The column.
        column: usize,
        /// The cell as written.
        value: String,
    },
    /// A wavelength of 0 nm.
    #[error("line {line}, column 1: wavelength {wavelength_nm} nm must be positive")]
    WavelengthNotPositive {
        /// The line.
        line: usize,
        /// The wavelength, in nm.
        wavelength_nm: f64,
    },
    /// A wavelength at or below the row before: interpolation needs sorted rows.
    #[error(
        "line {line}, column 1: wavelength {wavelength_nm} nm does not increase (the row before \
         has {previous_nm} nm); rows must be sorted by wavelength"
    )]
    NotIncreasing {
        /// The line.
        line: usize,
        /// The wavelength, in nm.
        wavelength_nm: f64,
        /// The wavelength of the row before, in nm.
        previous_nm: f64,
    },
    /// Fewer than the 2 data rows interpolation needs.
    #[error("the table has {rows} data row(s); at least 2 are needed to interpolate")]
    TooFewRows {
        /// Data rows found.
        rows: usize,
    },
    /// A sampling step that is not a positive number.
    #[error("the wavelength step must be a positive number of nm (got {step_nm:?})")]
    StepNotPositive {
        /// The step, in nm.
        step_nm: f64,
    },
    /// A step none of whose multiples lies in the table's range.
    #[error("no multiple of {step_nm:?} nm lies in the table's {lo_nm}–{hi_nm} nm")]
    NoStepInRange {
        /// The step, in nm.
        step_nm: f64,
        /// The table's first wavelength, in nm.
        lo_nm: f64,
        /// The table's last wavelength, in nm.
        hi_nm: f64,
    },
    /// A step so fine that a channel would get more than [`MAX_WAVELENGTHS`] wavelengths.
    #[error(
        "a step of {step_nm:?} nm gives {count:.0} wavelengths over {lo_nm}–{hi_nm} nm; at most \
         {MAX_WAVELENGTHS} per channel are simulated: use a step of at least {min_step_nm:.1} nm"
    )]
    TooManySamples {
        /// The step, in nm.
        step_nm: f64,
        /// The number of wavelengths it gives (a float: a tiny step gives more than fit a
        /// `usize`).
        count: f64,
        /// The table's first wavelength, in nm.
        lo_nm: f64,
        /// The table's last wavelength, in nm.
        hi_nm: f64,
        /// The smallest step that fits, rounded up to 0.1 nm.
        min_step_nm: f64,
    },
    /// No sample wavelength to make channels of.
    #[error("no sample wavelengths given")]
    NoSamples,
    /// A response without rows.
    #[error("the spectral table is empty")]
    EmptyTable,
    /// A sample wavelength that is NaN or infinite.
    #[error("sample wavelength {wavelength_nm} is not a finite number of nm")]
    SampleNotFinite {
        /// The sample wavelength, in nm.
        wavelength_nm: f64,
    },
    /// A sample wavelength outside the table's range (no extrapolation).
    #[error("sample wavelength {wavelength_nm:?} nm is outside the table ({lo_nm}–{hi_nm} nm)")]
    SampleOutside {
        /// The sample wavelength, in nm.
        wavelength_nm: f64,
        /// The table's first wavelength, in nm.
        lo_nm: f64,
        /// The table's last wavelength, in nm.
        hi_nm: f64,
    },
    /// A channel that would be all zero weights, which cannot be normalized.
    #[error(
        "channel {channel} has zero response at every sample wavelength; pick wavelengths where \
         it is sensitive"
    )]
    ZeroChannel {
        /// `R`, `G` or `B`.
        channel: &'static str,
    },
}
