//! Structure-aware fuzzing of every reader of untrusted files, as ordinary tests on stable Rust.
//!
//! Each reader gets near-valid inputs: a valid seed (a file of the repository, or one written
//! here with the crate's own writers) mutated a few times over: bits flipped, bytes and words
//! overwritten with edge values, byte ranges inserted, deleted or duplicated, the file cut or
//! spliced onto another seed, and in text a number replaced with an extreme one, a string with
//! an odd one, a line deleted or repeated. The property: the reader returns (no panic, no hang,
//! no multi-gigabyte allocation), and an error's message is one non-empty line.
//!
//! `UDC_FUZZ_CASES` sets the cases per reader (CI runs [`DEFAULT_CASES`]); `UDC_FUZZ_SEED` picks
//! another sequence of inputs than the fixed default one. A failing input is minimised and saved
//! under the system's temp folder (`udc-fuzz-findings/`); once understood it belongs in
//! `tests/corpus/fuzz/`, named `<reader>-<what>.<ext>`, which [`fuzz_corpus_replays`] replays.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::cell::Cell;
use std::io::Cursor;
use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock, mpsc};
use std::time::Duration;

use image::{DynamicImage, ImageBuffer, ImageFormat, Luma, Rgb, Rgba};
use ndarray::Array2;
use proptest::prelude::*;
use proptest::sample::Index;
use proptest::test_runner::{Config, RngSeed, TestCaseError, TestError, TestRunner};

use udc_studio::core::Progress;
use udc_studio::core::design::Design;
use udc_studio::core::mask::{MaskRegion, MaskSpec, Tone};
use udc_studio::core::phase::geometry::lenslet_count;
use udc_studio::core::phase::{GRID_LEN, HeightRounding, Lambda0, PhaseDesign, SamplingConvention};
use udc_studio::io::IoError;
use udc_studio::io::design::file::load_design;
use udc_studio::io::design::pattern::load_pattern_png;
use udc_studio::io::design::presets::load_preset;
use udc_studio::io::design::spectral::load_response_csv;
use udc_studio::io::mask::{
    ExportOptions, GdsCells, ImportOptions, MaskFormat, PngBits, export_mask, import_mask,
    import_opening,
};
use udc_studio::io::phase::design::{load_phase_design, phase_design_json};
use udc_studio::io::photo::hdr::{ExrPrecision, load_hdr_with_report, write_exr};
use udc_studio::io::photo::load_photo;
use udc_studio::io::photo::planes::read_planes;
use udc_studio::io::sweep::load_spec;
use udc_studio::io::sweep::manifest::{CSV_FILE, FORMAT, MANIFEST_FILE, Manifest, read_manifest};
use udc_studio::io::sweep::plots::{plot_data, plots_for};
use udc_studio::io::sweep::table::{ColumnKind, CsvWriter, Row, TableSchema, index_csv, read_csv};

/// Cases per reader when `UDC_FUZZ_CASES` is unset: the whole module stays within about 15 s
/// of wall time on two cores in the dev profile (docs/src/testing.md, "Fuzzing").
const DEFAULT_CASES: u32 = 800;
/// The default input sequence, fixed so that a CI failure reproduces.
const DEFAULT_SEED: u64 = 0x5eed;
/// Readers take milliseconds on these inputs; a case still running after this is a hang.
const HANG: Duration = Duration::from_secs(10);
/// Address space a single read may add: the inputs are kilobytes, so a gigabyte means a size
/// taken from the file unchecked, or a cap set above what a reader should ever need.
const HUGE_ALLOCATION_KIB: u64 = 1 << 20;
/// Mutations stop growing an input here (repeated lines, duplicated ranges).
const MAX_INPUT_BYTES: usize = 2 << 20;

fn config() -> Config {
    let cases = std::env::var("UDC_FUZZ_CASES")
        .ok()
        .map(|v| v.parse().expect("UDC_FUZZ_CASES is a number of cases"))
        .unwrap_or(DEFAULT_CASES);
    let seed = std::env::var("UDC_FUZZ_SEED")
        .ok()
        .map(|v| v.parse().expect("UDC_FUZZ_SEED is a number"))
        .unwrap_or(DEFAULT_SEED);
    Config {
        cases,
        // CI has no writable place for proptest's regression files; findings go to the corpus.
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(seed),
        // A slow reader must not turn minimisation into an unbounded run.
        max_shrink_time: 120_000,
        ..Config::default()
    }
}

// ---------------------------------------------------------------------------------------------
// Mutations

/// Byte values at the edges of signed and unsigned ranges, and 0.
const EDGE_BYTES: [u8; 6] = [0x00, 0xFF, 0x7F, 0x80, 0x01, 0xFE];
/// Word values at the edges of 16-, 32- and 64-bit ranges (written 2, 4 or 8 bytes wide).
const EDGE_WORDS: [u64; 12] = [
    0,
    1,
    0x7F,
    0x80,
    0x7FFF,
    0x8000,
    0xFFFF,
    0x7FFF_FFFF,
    0x8000_0000,
    0xFFFF_FFFF,
    0x4000_0000,
    u64::MAX,
];
/// Varint values past what 32 and 63 bits hold, where sums and products of coordinates and
/// counts overflow.
const EDGE_VARINTS: [u64; 6] = [
    1 << 31,
    1 << 32,
    1 << 62,
    i64::MAX as u64,
    1 << 63,
    u64::MAX,
];
/// What a number in a text file is replaced with: non-numbers, signs, overflows of every
/// integer width, underflow, and the big counts a size field should refuse.
const EXTREME_NUMBERS: [&str; 28] = [
    "NaN",
    "nan",
    "inf",
    "-inf",
    "Infinity",
    "-1",
    "0",
    "-0",
    "1e308",
    "-1e308",
    "1e309",
    "5e-324",
    "99999999999999999999",
    "18446744073709551615",
    "18446744073709551616",
    "9223372036854775807",
    "-9223372036854775808",
    "4294967295",
    "4294967296",
    "2147483648",
    "-2147483649",
    "65535",
    "65536",
    "1000000000",
    "1e9",
    "0.5",
    "1e",
    "--1",
];
/// What a string in a text file is replaced with: empty, escaped line breaks and control
/// characters (they reach messages that quote the file), a lone surrogate, a long run.
const ODD_STRINGS: [&str; 9] = [
    "",
    "\\n",
    "a\\nb",
    "\\r\\n",
    "\\u0000",
    "\\ud800",
    "\u{feff}",
    "../../x",
    "xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx",
];

#[derive(Debug, Clone)]
enum Op {
    FlipBit(Index, u8),
    Byte(Index, u8),
    Word {
        at: Index,
        value: u64,
        width: usize,
        little_endian: bool,
    },
    Insert(Index, Vec<u8>),
    Delete(Index, usize),
    Duplicate {
        from: Index,
        len: usize,
        to: Index,
    },
    /// An unsigned LEB128 number (OASIS's integers) in place of a byte.
    Varint(Index, u64),
    Truncate(Index),
    /// This input up to a cut, then another seed from a point on.
    Splice {
        seed: Index,
        cut: Index,
        from: Index,
    },
    Number(Index, &'static str),
    Text(Index, &'static str),
    DeleteLine(Index),
    RepeatLine(Index, usize),
}

#[derive(Debug, Clone)]
struct Case {
    seed: Index,
    ops: Vec<Op>,
    /// Recompute PNG chunk CRCs after mutating, so the mutation reaches the chunk's reader.
    fix_crcs: bool,
}

fn op(text: bool) -> BoxedStrategy<Op> {
    let bytes = prop_oneof![
        3 => (any::<Index>(), 0u8..8).prop_map(|(i, b)| Op::FlipBit(i, b)),
        2 => (any::<Index>(), prop::sample::select(&EDGE_BYTES[..])).prop_map(|(i, v)| Op::Byte(i, v)),
        1 => (any::<Index>(), any::<u8>()).prop_map(|(i, v)| Op::Byte(i, v)),
        2 => (
            any::<Index>(),
            prop::sample::select(&EDGE_WORDS[..]),
            prop::sample::select(vec![2usize, 4, 8]),
            any::<bool>()
        )
            .prop_map(|(at, value, width, little_endian)| Op::Word { at, value, width, little_endian }),
        1 => (any::<Index>(), prop::collection::vec(any::<u8>(), 1..16)).prop_map(|(i, v)| Op::Insert(i, v)),
        1 => (any::<Index>(), 1usize..64).prop_map(|(i, n)| Op::Delete(i, n)),
        1 => (any::<Index>(), 1usize..64, any::<Index>()).prop_map(|(from, len, to)| Op::Duplicate { from, len, to }),
        1 => (any::<Index>(), prop::sample::select(&EDGE_VARINTS[..])).prop_map(|(i, v)| Op::Varint(i, v)),
        1 => any::<Index>().prop_map(Op::Truncate),
        1 => (any::<Index>(), any::<Index>(), any::<Index>()).prop_map(|(seed, cut, from)| Op::Splice { seed, cut, from }),
    ];
    let words = prop_oneof![
        4 => (any::<Index>(), prop::sample::select(&EXTREME_NUMBERS[..])).prop_map(|(i, v)| Op::Number(i, v)),
        2 => (any::<Index>(), prop::sample::select(&ODD_STRINGS[..])).prop_map(|(i, v)| Op::Text(i, v)),
        1 => any::<Index>().prop_map(Op::DeleteLine),
        1 => (any::<Index>(), prop::sample::select(vec![1usize, 2, 1000])).prop_map(|(i, n)| Op::RepeatLine(i, n)),
    ];
    // Binary formats still carry text (DXF, Radiance headers, GDSII strings).
    let (b, w) = if text { (1, 2) } else { (4, 1) };
    prop_oneof![b => bytes, w => words].boxed()
}

fn case(text: bool) -> impl Strategy<Value = Case> {
    // Mostly one or two mutations: near-valid inputs get past the first checks.
    let ops = prop_oneof![
        4 => prop::collection::vec(op(text), 1..=1),
        3 => prop::collection::vec(op(text), 2..=2),
        2 => prop::collection::vec(op(text), 3..=6),
    ];
    (any::<Index>(), ops, any::<bool>()).prop_map(|(seed, ops, fix_crcs)| Case {
        seed,
        ops,
        fix_crcs,
    })
}

/// Spans of number tokens: runs of digits, signs, points and exponents holding a digit, not
/// glued to a word before them.
fn number_spans(b: &[u8]) -> Vec<(usize, usize)> {
    let numeric = |c: u8| c.is_ascii_digit() || matches!(c, b'.' | b'-' | b'+' | b'e' | b'E');
    let mut spans = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let glued = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
        if numeric(b[i]) && !glued {
            let start = i;
            while i < b.len() && numeric(b[i]) {
                i += 1;
            }
            if b[start..i].iter().any(u8::is_ascii_digit) {
                spans.push((start, i));
            }
        } else {
            i += 1;
        }
    }
    spans
}

/// Spans of the contents of double-quoted strings (escaped quotes skipped).
fn string_spans(b: &[u8]) -> Vec<(usize, usize)> {
    let quotes: Vec<usize> = (0..b.len())
        .filter(|&i| b[i] == b'"' && (i == 0 || b[i - 1] != b'\\'))
        .collect();
    quotes.chunks_exact(2).map(|q| (q[0] + 1, q[1])).collect()
}

/// Spans of lines, each with its line break.
fn line_spans(b: &[u8]) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut start = 0;
    for (i, c) in b.iter().enumerate() {
        if *c == b'\n' {
            spans.push((start, i + 1));
            start = i + 1;
        }
    }
    if start < b.len() {
        spans.push((start, b.len()));
    }
    spans
}

fn pick(spans: &[(usize, usize)], i: &Index) -> Option<(usize, usize)> {
    (!spans.is_empty()).then(|| spans[i.index(spans.len())])
}

impl Op {
    fn apply(&self, b: &mut Vec<u8>, seeds: &[Seed]) {
        let at = |i: &Index, len: usize| (len > 0).then(|| i.index(len));
        match self {
            Op::FlipBit(i, bit) => {
                if let Some(k) = at(i, b.len()) {
                    b[k] ^= 1 << bit;
                }
            }
            Op::Byte(i, v) => {
                if let Some(k) = at(i, b.len()) {
                    b[k] = *v;
                }
            }
            Op::Word {
                at: i,
                value,
                width,
                little_endian,
            } => {
                if let Some(k) = at(i, b.len()) {
                    let le = value.to_le_bytes();
                    let mut word: Vec<u8> = le[..*width].to_vec();
                    if !little_endian {
                        word.reverse();
                    }
                    for (j, v) in word.into_iter().enumerate() {
                        if let Some(slot) = b.get_mut(k + j) {
                            *slot = v;
                        }
                    }
                }
            }
            Op::Insert(i, v) => {
                let k = at(i, b.len() + 1).unwrap_or(0);
                b.splice(k..k, v.iter().copied());
            }
            Op::Delete(i, n) => {
                if let Some(k) = at(i, b.len()) {
                    b.drain(k..(k + n).min(b.len()));
                }
            }
            Op::Duplicate { from, len, to } => {
                if let Some(k) = at(from, b.len()) {
                    let piece = b[k..(k + len).min(b.len())].to_vec();
                    let t = to.index(b.len() + 1);
                    b.splice(t..t, piece);
                }
            }
            Op::Varint(i, v) => {
                if let Some(k) = at(i, b.len()) {
                    let mut leb = Vec::new();
                    let mut rest = *v;
                    while rest >= 0x80 {
                        leb.push((rest & 0x7f) as u8 | 0x80);
                        rest >>= 7;
                    }
                    leb.push(rest as u8);
                    b.splice(k..=k, leb);
                }
            }
            Op::Truncate(i) => {
                let k = i.index(b.len() + 1);
                b.truncate(k);
            }
            Op::Splice { seed, cut, from } => {
                let other = &seeds[seed.index(seeds.len())].bytes;
                let k = cut.index(b.len() + 1);
                let f = from.index(other.len() + 1);
                b.truncate(k);
                b.extend_from_slice(&other[f..]);
            }
            Op::Number(i, v) => {
                if let Some((s, e)) = pick(&number_spans(b), i) {
                    b.splice(s..e, v.bytes());
                }
            }
            Op::Text(i, v) => {
                if let Some((s, e)) = pick(&string_spans(b), i) {
                    b.splice(s..e, v.bytes());
                }
            }
            Op::DeleteLine(i) => {
                if let Some((s, e)) = pick(&line_spans(b), i) {
                    b.drain(s..e);
                }
            }
            Op::RepeatLine(i, n) => {
                if let Some((s, e)) = pick(&line_spans(b), i) {
                    let mut line = b[s..e].to_vec();
                    if line.last() != Some(&b'\n') {
                        line.push(b'\n');
                    }
                    let copies: Vec<u8> = line.repeat(*n);
                    b.splice(e..e, copies);
                }
            }
        }
        b.truncate(MAX_INPUT_BYTES);
    }
}

impl Case {
    fn input(&self, seeds: &[Seed]) -> (usize, Vec<u8>) {
        let k = self.seed.index(seeds.len());
        let mut b = seeds[k].bytes.clone();
        for op in &self.ops {
            op.apply(&mut b, seeds);
        }
        if self.fix_crcs {
            fix_png_crcs(&mut b);
        }
        (k, b)
    }
}

const PNG_SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";

/// Rewrites the CRC of every whole chunk of a PNG, so a mutated chunk is parsed, not refused.
fn fix_png_crcs(b: &mut [u8]) {
    if !b.starts_with(PNG_SIGNATURE) {
        return;
    }
    let mut pos = PNG_SIGNATURE.len();
    while pos + 12 <= b.len() {
        let len = u32::from_be_bytes(b[pos..pos + 4].try_into().unwrap()) as usize;
        let Some(end) = (pos + 8).checked_add(len).filter(|e| e + 4 <= b.len()) else {
            return;
        };
        let crc = crc32fast::hash(&b[pos + 4..end]);
        b[end..end + 4].copy_from_slice(&crc.to_be_bytes());
        pos = end + 4;
    }
}

// ---------------------------------------------------------------------------------------------
// The property

type Reader = Arc<dyn Fn(&Path) -> Result<(), IoError> + Send + Sync>;

/// A valid (or committed malformed) input and the file name a reader gets it under.
struct Seed {
    file: String,
    bytes: Vec<u8>,
}

fn seed(file: impl Into<String>, bytes: Vec<u8>) -> Seed {
    Seed {
        file: file.into(),
        bytes,
    }
}

/// `VmPeak` and `VmSize` of this process in KiB (Linux; `None` elsewhere).
fn address_space_kib() -> Option<(u64, u64)> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let field = |name: &str| -> Option<u64> {
        let line = status.lines().find(|l| l.starts_with(name))?;
        line[name.len()..]
            .trim()
            .trim_end_matches("kB")
            .trim()
            .parse()
            .ok()
    };
    Some((field("VmPeak:")?, field("VmSize:")?))
}

/// Whether this process runs this test alone (nextest, or a corpus replay's child), so its
/// address space is the reader's.
fn alone_in_process() -> bool {
    std::env::var("NEXTEST_EXECUTION_MODE").is_ok_and(|m| m == "process-per-test")
        || std::env::var_os(REPLAY_VAR).is_some()
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(a panic without a message)".into())
}

/// Keeps a failing input where it outlives the test, and says where.
fn save_finding(kind: &str, file: &str, bytes: &[u8]) -> String {
    let dir = std::env::temp_dir().join("udc-fuzz-findings");
    let hash = bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3)
    });
    let ext = Path::new(file)
        .extension()
        .map_or(String::new(), |e| format!(".{}", e.to_string_lossy()));
    let path = dir.join(format!("{kind}-{hash:016x}{ext}"));
    match std::fs::create_dir_all(&dir).and_then(|()| std::fs::write(&path, bytes)) {
        Ok(()) => format!("input saved as {}", path.display()),
        Err(e) => format!("input not saved ({e})"),
    }
}

/// Why an input fails the property.
struct Failure {
    /// The reader had not returned after [`HANG`]; its thread is left running.
    hang: bool,
    message: String,
}

impl From<String> for Failure {
    fn from(message: String) -> Self {
        Failure {
            hang: false,
            message,
        }
    }
}

/// Runs `read` on `bytes` written as `work/case/file` and checks the property; `Ok` says
/// whether the reader accepted the input.
fn check(
    kind: &str,
    read: &Reader,
    work: &Path,
    file: &str,
    bytes: &[u8],
) -> Result<bool, Failure> {
    let dir = work.join("case");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("case folder");
    let path = dir.join(file);
    std::fs::write(&path, bytes).expect("write the case");
    let before = address_space_kib();
    let (tx, rx) = mpsc::channel();
    let reader = Arc::clone(read);
    let worker = std::thread::Builder::new()
        .name(format!("fuzz-{kind}"))
        .spawn(move || {
            let outcome = std::panic::catch_unwind(AssertUnwindSafe(|| reader(&path)));
            let _ = tx.send(outcome.map(|r| r.err().map(|e| e.to_string())));
        })
        .expect("spawn the reader");
    let outcome = match rx.recv_timeout(HANG) {
        Ok(outcome) => outcome,
        Err(mpsc::RecvTimeoutError::Timeout) => {
            return Err(Failure {
                hang: true,
                message: format!("{kind}: still reading after {HANG:?} (a hang)"),
            });
        }
        Err(mpsc::RecvTimeoutError::Disconnected) => {
            return Err(format!("{kind}: the reader's thread died without a result").into());
        }
    };
    let _ = worker.join();
    let accepted = match outcome {
        Err(payload) => {
            return Err(format!("{kind}: panicked: {}", panic_message(&*payload)).into());
        }
        Ok(Some(message)) => {
            if message.trim().is_empty() {
                return Err(format!("{kind}: an error with an empty message").into());
            }
            if message.contains(['\n', '\r']) {
                return Err(format!("{kind}: a message of several lines: {message:?}").into());
            }
            false
        }
        Ok(None) => true,
    };
    // Only a peak this read raised is its own: an earlier case's stays in VmPeak.
    if let (Some((peak_before, size_before)), Some((peak_after, _)), true) =
        (before, address_space_kib(), alone_in_process())
        && peak_after > peak_before
        && peak_after - size_before > HUGE_ALLOCATION_KIB
    {
        return Err(format!(
            "{kind}: the read reserved {} MiB of address space for a {}-byte input",
            (peak_after - size_before) / 1024,
            bytes.len()
        )
        .into());
    }
    Ok(accepted)
}

/// Runs the configured number of mutated inputs of `kind` through its reader.
fn fuzz(kind: &'static str) {
    let seeds = seeds(kind);
    assert!(!seeds.is_empty(), "{kind}: no seeds");
    let read = reader(kind);
    let work = tempfile::Builder::new()
        .prefix(&format!("udc-fuzz-{kind}-"))
        .tempdir()
        .expect("temp dir");
    let mut runner = TestRunner::new(config());
    // After a hang every case passes: shrinking would only start more hanging threads, so the
    // hanging input itself is reported.
    let hung = Cell::new(false);
    // How many inputs a reader accepted: mutations that never get past the header would test
    // little, and this shows it (`--no-capture`).
    let (read_ok, refused) = (Cell::new(0u32), Cell::new(0u32));
    let result = runner.run(&case(is_text(kind)), |c| {
        if hung.get() {
            return Ok(());
        }
        let (k, bytes) = c.input(&seeds);
        let outcome = check(kind, &read, work.path(), &seeds[k].file, &bytes);
        match &outcome {
            Ok(true) => read_ok.set(read_ok.get() + 1),
            Ok(false) => refused.set(refused.get() + 1),
            Err(f) => hung.set(f.hang),
        }
        outcome
            .map(drop)
            .map_err(|f| TestCaseError::fail(f.message))
    });
    eprintln!(
        "{kind}: {} seeds, {} inputs read, {} refused",
        seeds.len(),
        read_ok.get(),
        refused.get()
    );
    match result {
        Ok(()) => {}
        Err(TestError::Fail(why, c)) => {
            let (k, bytes) = c.input(&seeds);
            let saved = save_finding(kind, &seeds[k].file, &bytes);
            panic!(
                "{why}; minimal input: seed {k} ({}) after {c:?}; {saved}",
                seeds[k].file
            );
        }
        Err(e) => panic!("{kind}: {e}"),
    }
}

fn is_text(kind: &str) -> bool {
    matches!(
        kind,
        "design" | "phase" | "spec" | "spectral" | "sweep" | "dxf"
    )
}

// ---------------------------------------------------------------------------------------------
// Readers

/// The design the PNG mask seeds are exported from, which their import lays out again.
fn mask_design() -> &'static Design {
    static DESIGN: OnceLock<Design> = OnceLock::new();
    DESIGN.get_or_init(|| load_preset("l2inv-random").expect("preset"))
}

/// Each reader as the studio and the commands call it. `kind` is also the corpus prefix.
fn reader(kind: &str) -> Reader {
    match kind {
        "oasis" | "gds" | "dxf" => Arc::new(|p: &Path| {
            // No window: the polygons' bounding box sizes the grid, as `import_mask` does by
            // default, so a coordinate from the file decides an allocation.
            import_mask(p, &ImportOptions::default()).map(drop)
        }),
        "maskpng" => Arc::new(|p: &Path| import_opening(p, mask_design()).map(drop)),
        "photo" => Arc::new(|p: &Path| load_photo::<f64>(p, None).map(drop)),
        "hdr" => Arc::new(|p: &Path| load_hdr_with_report(p).map(drop)),
        "planes" => Arc::new(|p: &Path| read_planes(p).map(drop)),
        "pattern" => Arc::new(|p: &Path| load_pattern_png(p).map(drop)),
        "design" => Arc::new(|p: &Path| load_design(p).map(drop)),
        "phase" => Arc::new(|p: &Path| load_phase_design(p).map(drop)),
        "spec" => Arc::new(|p: &Path| load_spec(p).map(drop)),
        "spectral" => Arc::new(|p: &Path| load_response_csv(p).map(drop)),
        "sweep" => {
            let (manifest, csv) = sweep_folder();
            Arc::new(move |p: &Path| read_sweep_folder(p, &manifest, &csv))
        }
        other => panic!("no reader for `{other}`"),
    }
}

/// A results folder as the studio, the plots, `sweep merge` and a resumed run read it; `p` is
/// the mutated file, the other one is written valid beside it.
fn read_sweep_folder(p: &Path, manifest: &[u8], csv: &[u8]) -> Result<(), IoError> {
    let dir = p.parent().expect("a folder");
    let (other, bytes) = if p.ends_with(MANIFEST_FILE) {
        (CSV_FILE, csv)
    } else {
        (MANIFEST_FILE, manifest)
    };
    let other = dir.join(other);
    std::fs::write(&other, bytes).map_err(|e| IoError::file("write", &other, e))?;
    let m = read_manifest(dir)?;
    let table = dir.join(CSV_FILE);
    read_csv(&table, &m.schema, false, |_| Ok(()))?;
    index_csv(&table, &m.schema, |_, _| Ok(()))?;
    for plot in plots_for(&m) {
        plot_data(dir, &m, &plot)?;
    }
    read_csv(&table, &m.schema, true, |_| Ok(()))
}

/// The file name a corpus file of `kind` with extension `ext` is read under.
fn destination(kind: &str, ext: &str) -> String {
    match (kind, ext) {
        ("sweep", "json") => MANIFEST_FILE.into(),
        ("sweep", _) => CSV_FILE.into(),
        _ => format!("input.{ext}"),
    }
}

// ---------------------------------------------------------------------------------------------
// Seeds

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// The files of a repository folder whose names end in one of `exts`, as seeds read under
/// `input.<ext>`.
fn repo_files(dir: &str, exts: &[&str]) -> Vec<Seed> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(repo(dir))
        .unwrap_or_else(|e| panic!("{dir}: {e}"))
        .map(|e| e.expect("entry").path())
        .filter(|p| {
            p.extension()
                .is_some_and(|e| exts.contains(&e.to_string_lossy().as_ref()))
        })
        .collect();
    paths.sort();
    paths
        .into_iter()
        .map(|p| {
            let ext = p.extension().expect("ext").to_string_lossy().into_owned();
            seed(
                format!("input.{ext}"),
                std::fs::read(&p).expect("read a seed"),
            )
        })
        .collect()
}

fn encode(img: DynamicImage, format: ImageFormat) -> Vec<u8> {
    let mut out = Cursor::new(Vec::new());
    img.write_to(&mut out, format).expect("encode a seed image");
    out.into_inner()
}

fn rgb8(w: u32, h: u32) -> DynamicImage {
    DynamicImage::ImageRgb8(ImageBuffer::from_fn(w, h, |x, y| {
        Rgb([(x * 16) as u8, (y * 16) as u8, ((x + y) * 8) as u8])
    }))
}

fn rgb32f(w: u32, h: u32) -> DynamicImage {
    DynamicImage::ImageRgb32F(ImageBuffer::from_fn(w, h, |x, y| {
        Rgb([x as f32 * 0.1, y as f32 * 3.0, 100.0 / (1.0 + x as f32)])
    }))
}

fn grey16(side: u32) -> DynamicImage {
    DynamicImage::ImageLuma16(ImageBuffer::from_fn(side, side, |x, y| {
        Luma([if (x + y) % 3 == 0 { 65535 } else { 0 }])
    }))
}

fn rgba8(side: u32) -> DynamicImage {
    DynamicImage::ImageRgba8(ImageBuffer::from_fn(side, side, |x, y| {
        Rgba([(x * 40) as u8, 200, (y * 40) as u8, 128])
    }))
}

/// A 1-bit grey PNG with a metric pixel size and notes, as the mask export writes them.
fn png_1bit(side: u32) -> Vec<u8> {
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, side, side);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::One);
    enc.set_pixel_dims(Some(png::PixelDimensions {
        xppu: 1_000_000,
        yppu: 1_000_000,
        unit: png::Unit::Meter,
    }));
    enc.add_text_chunk(
        "Description".into(),
        "TONE=OPEN: DRAWN = OPEN (CLEAR)\nREGION=pixel GRID_NM=1".into(),
    )
    .expect("text chunk");
    let row = side.div_ceil(8) as usize;
    let data: Vec<u8> = (0..row * side as usize)
        .map(|i| if i % 3 == 0 { 0xF0 } else { 0x0F })
        .collect();
    let mut w = enc.write_header().expect("header");
    w.write_image_data(&data).expect("data");
    w.finish().expect("finish");
    out
}

fn exr(planes: &[Array2<f64>], precision: ExrPrecision) -> Vec<u8> {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("seed.exr");
    let refs: Vec<&Array2<f64>> = planes.iter().collect();
    write_exr(&path, &refs, precision).expect("write a seed EXR");
    std::fs::read(&path).expect("read it back")
}

fn plane(h: usize, w: usize, k: f64) -> Array2<f64> {
    Array2::from_shape_fn((h, w), |(y, x)| k * (1.0 + x as f64) / (1.0 + y as f64))
}

fn exr_seeds() -> Vec<Seed> {
    let rgb = [plane(6, 9, 1.0), plane(6, 9, 50.0), plane(6, 9, 0.01)];
    vec![
        seed("input.exr", exr(&rgb, ExrPrecision::Half)),
        seed("input.exr", exr(&rgb, ExrPrecision::Float)),
        seed("input.exr", exr(&[plane(5, 5, 2.0)], ExrPrecision::Float)),
        seed("input.exr", encode(rgb32f(7, 4), ImageFormat::OpenExr)),
    ]
}

fn radiance_seeds() -> Vec<Seed> {
    vec![
        seed("input.hdr", encode(rgb32f(8, 5), ImageFormat::Hdr)),
        seed("input.hdr", encode(rgb32f(3, 3), ImageFormat::Hdr)),
    ]
}

fn png_seeds() -> Vec<Seed> {
    vec![
        seed("input.png", encode(rgb8(12, 9), ImageFormat::Png)),
        seed("input.png", encode(grey16(9), ImageFormat::Png)),
        seed("input.png", encode(rgba8(6), ImageFormat::Png)),
        seed("input.png", png_1bit(11)),
    ]
}

fn tiff_seeds() -> Vec<Seed> {
    vec![
        seed("input.tif", encode(rgb8(10, 7), ImageFormat::Tiff)),
        seed("input.tif", encode(grey16(8), ImageFormat::Tiff)),
        seed("input.tif", encode(rgb32f(5, 6), ImageFormat::Tiff)),
    ]
}

/// Masks written by the io crate's own exporter: a periodic and a randomly tiled design, one
/// pixel and a block, both tones, both GDSII cell layouts.
fn exported_masks(format: MaskFormat) -> Vec<Seed> {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut out = Vec::new();
    let variants = [
        (
            "open-aperture",
            MaskRegion::PIXEL,
            Tone::Open,
            GdsCells::Strans,
        ),
        (
            "l2inv-random",
            MaskRegion::Block { cols: 3, rows: 2 },
            Tone::Chrome,
            GdsCells::Strans,
        ),
        (
            "l2inv-random",
            MaskRegion::PIXEL,
            Tone::Open,
            GdsCells::PerOrientation,
        ),
    ];
    for (k, (preset, region, tone, gds_cells)) in variants.into_iter().enumerate() {
        if format != MaskFormat::Gds && gds_cells == GdsCells::PerOrientation {
            continue;
        }
        let design = load_preset(preset).expect("preset");
        let options = ExportOptions {
            format,
            spec: MaskSpec {
                region,
                tone,
                ..MaskSpec::default()
            },
            gds_cells,
            png_bits: if k == 1 { PngBits::One } else { PngBits::Eight },
            um_per_px: 2.0,
            deterministic: true,
            ..ExportOptions::default()
        };
        let path = dir.path().join(format!("m{k}.{}", format.extension()));
        export_mask(&design, &options, &path, &Progress::new()).expect("export a seed mask");
        out.push(seed(
            format!("input.{}", format.extension()),
            std::fs::read(&path).expect("read the seed mask"),
        ));
    }
    out
}

/// A GDSII library nested six levels deep through arrays and rotated, mirrored references,
/// with a note: mutations of its counts and steps reach the reference expansion.
fn gds_hierarchy() -> Vec<u8> {
    use gds21::{
        GdsArrayRef, GdsBoundary, GdsElement, GdsLibrary, GdsPoint, GdsStrans, GdsStruct,
        GdsStructRef, GdsTextElem,
    };
    let mut lib = GdsLibrary::new("FUZZ");
    for level in 0..6 {
        let mut s = GdsStruct::new(format!("L{level}"));
        if level < 5 {
            let child = format!("L{}", level + 1);
            s.elems.push(GdsElement::GdsArrayRef(GdsArrayRef {
                name: child.clone(),
                xy: [
                    GdsPoint::new(0, 0),
                    GdsPoint::new(2_000, 0),
                    GdsPoint::new(0, 2_000),
                ],
                cols: 2,
                rows: 2,
                ..Default::default()
            }));
            s.elems.push(GdsElement::GdsStructRef(GdsStructRef {
                name: child,
                xy: GdsPoint::new(5_000, -3_000),
                strans: Some(GdsStrans {
                    reflected: true,
                    mag: Some(1.5),
                    angle: Some(90.0),
                    ..Default::default()
                }),
                ..Default::default()
            }));
        } else {
            s.elems.push(GdsElement::GdsBoundary(GdsBoundary {
                layer: 1,
                datatype: 0,
                xy: GdsPoint::vec(&[(0, 0), (800, 0), (800, 600), (0, 600), (0, 0)]),
                ..Default::default()
            }));
            s.elems.push(GdsElement::GdsTextElem(GdsTextElem {
                string: "TONE=CHROME: DRAWN = CHROME".into(),
                layer: 2,
                xy: GdsPoint::new(0, 0),
                ..Default::default()
            }));
        }
        lib.structs.push(s);
    }
    let mut out = Vec::new();
    lib.write(&mut out).expect("write the GDSII seed");
    out
}

/// OASIS records written by hand (SEMI P39), for what the exporter never writes: CBLOCKs,
/// point lists, nested placements with repetitions, implicit names.
mod oas {
    use std::io::Write;

    pub const MAGIC: &[u8] = b"%SEMI-OASIS\r\n";

    pub fn u(out: &mut Vec<u8>, mut v: u64) {
        loop {
            let b = (v & 0x7f) as u8;
            v >>= 7;
            if v == 0 {
                out.push(b);
                return;
            }
            out.push(b | 0x80);
        }
    }

    pub fn s(out: &mut Vec<u8>, v: i64) {
        u(out, (v.unsigned_abs() << 1) | u64::from(v < 0));
    }

    pub fn string(out: &mut Vec<u8>, text: &str) {
        u(out, text.len() as u64);
        out.extend_from_slice(text.as_bytes());
    }

    /// START with version 1.0, 1000 units per µm and the table offsets in it (all zero).
    pub fn start(out: &mut Vec<u8>) {
        out.extend_from_slice(MAGIC);
        u(out, 1);
        string(out, "1.0");
        u(out, 0);
        u(out, 1000);
        u(out, 0);
        for _ in 0..12 {
            u(out, 0);
        }
    }

    pub fn end(out: &mut Vec<u8>) {
        u(out, 2);
        string(out, "");
        u(out, 0);
    }

    pub fn cellname(out: &mut Vec<u8>, name: &str) {
        u(out, 3);
        string(out, name);
    }

    pub fn cell(out: &mut Vec<u8>, refnum: u64) {
        u(out, 13);
        u(out, refnum);
    }

    /// A placement of cell `refnum` at (x, y) repeated on an `nx × ny` grid of step (sx, sy).
    pub fn placement(out: &mut Vec<u8>, refnum: u64, xy: [i64; 2], grid: [u64; 4]) {
        u(out, 17);
        out.push(0xC0 | 0x20 | 0x10 | 0x08);
        u(out, refnum);
        s(out, xy[0]);
        s(out, xy[1]);
        u(out, 1);
        u(out, grid[0] - 2);
        u(out, grid[1] - 2);
        u(out, grid[2]);
        u(out, grid[3]);
    }

    pub fn rectangle(out: &mut Vec<u8>, layer: u64, wh: [u64; 2], xy: [i64; 2]) {
        u(out, 20);
        out.push(0x01 | 0x02 | 0x40 | 0x20 | 0x10 | 0x08);
        u(out, layer);
        u(out, 0);
        u(out, wh[0]);
        u(out, wh[1]);
        s(out, xy[0]);
        s(out, xy[1]);
    }

    /// A polygon on layer 1/0 from a Manhattan point list (type 0) and a g-delta one (type 4).
    pub fn polygons(out: &mut Vec<u8>) {
        u(out, 21);
        out.push(0x01 | 0x02 | 0x20 | 0x10 | 0x08);
        u(out, 1);
        u(out, 0);
        u(out, 0);
        u(out, 3);
        for d in [400, 300, -200] {
            s(out, d);
        }
        s(out, 100);
        s(out, 100);
        u(out, 21);
        out.push(0x20 | 0x10);
        u(out, 4);
        u(out, 3);
        // g-deltas of the second form: x with its sign in bit 1, then y.
        for (x, y) in [(500i64, 0i64), (0, 500), (-250, 250)] {
            u(out, (x.unsigned_abs() << 2) | (u64::from(x < 0) << 1) | 1);
            s(out, y);
        }
        s(out, -900);
    }

    pub fn text(out: &mut Vec<u8>, text: &str) {
        u(out, 19);
        out.push(0x40 | 0x01 | 0x02 | 0x10 | 0x08);
        string(out, text);
        u(out, 2);
        u(out, 0);
        s(out, 0);
        s(out, -50);
    }

    /// `records` deflated into a CBLOCK.
    pub fn cblock(out: &mut Vec<u8>, records: &[u8]) {
        let mut z = flate2::write::DeflateEncoder::new(Vec::new(), flate2::Compression::best());
        z.write_all(records).expect("deflate");
        let packed = z.finish().expect("deflate");
        u(out, 34);
        u(out, 0);
        u(out, records.len() as u64);
        u(out, packed.len() as u64);
        out.extend_from_slice(&packed);
    }

    /// Cells `L0` … `L{depth}`, each placing the next on an `n × n` grid; the last holds a
    /// rectangle, polygons and a note.
    pub fn hierarchy(depth: u64, n: u64) -> Vec<u8> {
        let mut out = Vec::new();
        for level in 0..=depth {
            cellname(&mut out, &format!("L{level}"));
        }
        for level in 0..depth {
            cell(&mut out, level);
            placement(&mut out, level + 1, [100, -40], [n, n, 3_000, 2_500]);
        }
        cell(&mut out, depth);
        rectangle(&mut out, 1, [1_000, 700], [0, 0]);
        polygons(&mut out);
        text(&mut out, "TONE=OPEN: DRAWN = OPEN (CLEAR)");
        out
    }

    pub fn file(body: &[u8], compressed: bool) -> Vec<u8> {
        let mut out = Vec::new();
        start(&mut out);
        if compressed {
            cblock(&mut out, body);
        } else {
            out.extend_from_slice(body);
        }
        end(&mut out);
        out
    }
}

fn phase_seeds() -> Vec<Seed> {
    let mut designs = vec![PhaseDesign::thesis(42.0, 1.0)];
    let mut d = PhaseDesign::thesis(84.0, 5.0);
    d.lambda0 = Lambda0::Uniform;
    d.height_step_um = Some(0.2);
    d.height_rounding = HeightRounding::Nearest;
    d.sampling = SamplingConvention::Centred;
    designs.push(d);
    // Per-lenslet lists and counts are only valid for the design's own number of lenslets.
    let mut d = PhaseDesign::thesis(42.0, 1.0);
    let n = lenslet_count(&d);
    d.lambda0 = Lambda0::PerLenslet {
        nm: (0..n).map(|k| 400.0 + (k % 30) as f64 * 10.0).collect(),
    };
    designs.push(d);
    let mut d = PhaseDesign::thesis(42.0, 2.0);
    let n = lenslet_count(&d);
    d.lambda0 = Lambda0::Counts {
        counts: (0..GRID_LEN)
            .map(|k| n / GRID_LEN + usize::from(k < n % GRID_LEN))
            .collect(),
    };
    designs.push(d);
    let mut seeds: Vec<Seed> = designs
        .iter()
        .map(|d| seed("input.json", phase_design_json(d).into_bytes()))
        .collect();
    seeds.extend(repo_files("tests/corpus/phase", &["json"]));
    seeds
}

/// A results folder as a sweep leaves it: the manifest of the committed DPI study's spec (it
/// has plots) and a table with text, integer and metric columns and one failed point.
fn sweep_folder() -> (Vec<u8>, Vec<u8>) {
    static FOLDER: OnceLock<(Vec<u8>, Vec<u8>)> = OnceLock::new();
    FOLDER
        .get_or_init(|| {
            let spec = load_spec(&repo("presets/sweeps/dpi-tiling-seed.toml")).expect("spec");
            let schema = TableSchema {
                params: vec![
                    ("preset".into(), ColumnKind::Text),
                    ("tiling".into(), ColumnKind::Text),
                    ("seed".into(), ColumnKind::Int),
                ],
                metrics: vec![
                    "auc_radial_min_mean".into(),
                    "channels.G.auc_radial_min".into(),
                    "ltr".into(),
                    "invertibility_loss".into(),
                ],
            };
            let dir = tempfile::tempdir().expect("temp dir");
            let csv = dir.path().join(CSV_FILE);
            let mut w = CsvWriter::create(&csv, &schema).expect("table");
            for point in 0..5u64 {
                let params = vec![
                    ["toled-150dpi", "toled-300dpi"][point as usize % 2].to_string(),
                    ["repeat", "random-4"][point as usize / 2 % 2].to_string(),
                    point.to_string(),
                ];
                let row = if point == 3 {
                    Row::failed(
                        point,
                        format!("h{point}"),
                        params,
                        4,
                        "out of memory".into(),
                    )
                } else {
                    Row {
                        point,
                        hash: format!("h{point}"),
                        params,
                        metrics: vec![0.5 + point as f64 * 0.01, 0.25, 0.031, 1.5e-3],
                        design_hash: format!("d{point}"),
                        error: String::new(),
                        tool_version: "0.1.0".into(),
                    }
                };
                w.write(&row).expect("row");
            }
            w.finish().expect("table");
            let manifest = Manifest {
                format: FORMAT.into(),
                version: 1,
                spec_hash: udc_studio::io::sweep::manifest::spec_hash(&spec),
                spec,
                points: 60,
                shard: [0, 1],
                schema,
                tool_version: "0.1.0".into(),
                rows: 5,
                failed: 1,
                complete: false,
                elapsed_s: 12.5,
                points_per_s: 0.4,
                threads: 2,
            };
            let json = serde_json::to_vec_pretty(&manifest).expect("manifest");
            (json, std::fs::read(&csv).expect("table"))
        })
        .clone()
}

fn seeds(kind: &str) -> Vec<Seed> {
    let mut s = Vec::new();
    match kind {
        "oasis" => {
            s.extend(exported_masks(MaskFormat::Oas));
            s.push(seed("input.oas", oas::file(&oas::hierarchy(4, 2), false)));
            s.push(seed("input.oas", oas::file(&oas::hierarchy(3, 3), true)));
        }
        "gds" => {
            s.extend(exported_masks(MaskFormat::Gds));
            s.push(seed("input.gds", gds_hierarchy()));
            s.extend(repo_files("tests/corpus/mask", &["gds"]));
        }
        "dxf" => {
            s.extend(exported_masks(MaskFormat::Dxf));
            s.extend(repo_files("tests/corpus/mask", &["dxf"]));
        }
        "maskpng" => {
            s.extend(exported_masks(MaskFormat::Png));
            s.push(seed("input.png", png_1bit(16)));
        }
        "photo" => {
            s.extend(png_seeds());
            s.extend(tiff_seeds());
            s.extend(exr_seeds());
            s.extend(radiance_seeds());
            s.push(seed("input.jpg", encode(rgb8(16, 8), ImageFormat::Jpeg)));
            s.extend(repo_files("tests/corpus/image", &["png"]));
            s.extend(repo_files("tests/corpus/hdr", &["exr", "hdr"]));
        }
        "hdr" => {
            s.extend(exr_seeds());
            s.extend(radiance_seeds());
            s.extend(repo_files("tests/corpus/hdr", &["exr", "hdr"]));
        }
        "planes" => {
            s.extend(png_seeds());
            s.extend(tiff_seeds());
            s.extend(exr_seeds());
            s.extend(repo_files("tests/corpus/image", &["png"]));
        }
        "pattern" => {
            s.push(seed("input.png", encode(grey16(9), ImageFormat::Png)));
            s.push(seed("input.png", encode(rgba8(6), ImageFormat::Png)));
            s.push(seed("input.png", png_1bit(11)));
            s.push(seed("input.tif", encode(grey16(7), ImageFormat::Tiff)));
            s.push(seed(
                "input.exr",
                exr(&[plane(6, 6, 1.0)], ExrPrecision::Half),
            ));
            s.extend(repo_files("assets/pixel-patterns", &["png"]));
            s.extend(repo_files("tests/corpus/image", &["png"]));
        }
        "design" => {
            // The small presets: the 34 kB ones only repeat the same structure at length.
            s.extend(
                repo_files("presets", &["json"])
                    .into_iter()
                    .filter(|p| p.bytes.len() < 8_000),
            );
            s.extend(repo_files("presets/reproduce/designs/fig3.9", &["json"]));
            s.extend(repo_files("tests/corpus/design", &["json"]));
        }
        "phase" => s.extend(phase_seeds()),
        "spec" => {
            s.extend(repo_files("tests/sweep", &["toml"]));
            s.extend(repo_files("presets/sweeps", &["toml"]));
            let spec = load_spec(&repo("tests/sweep/tiny.toml")).expect("spec");
            s.push(seed(
                "input.json",
                serde_json::to_vec_pretty(&spec).expect("spec as JSON"),
            ));
        }
        "spectral" => {
            s.extend(repo_files("assets/spectral", &["csv"]));
            s.extend(repo_files("tests/corpus/spectral", &["csv"]));
        }
        "sweep" => {
            let (manifest, csv) = sweep_folder();
            s.push(seed(MANIFEST_FILE, manifest));
            s.push(seed(CSV_FILE, csv));
        }
        other => panic!("no seeds for `{other}`"),
    }
    s
}

// ---------------------------------------------------------------------------------------------
// The tests

#[test]
fn fuzz_oasis_mask() {
    fuzz("oasis");
}

#[test]
fn fuzz_gds_mask() {
    fuzz("gds");
}

#[test]
fn fuzz_dxf_mask() {
    fuzz("dxf");
}

#[test]
fn fuzz_png_mask() {
    fuzz("maskpng");
}

#[test]
fn fuzz_photo() {
    fuzz("photo");
}

#[test]
fn fuzz_hdr_scene() {
    fuzz("hdr");
}

#[test]
fn fuzz_image_planes() {
    fuzz("planes");
}

#[test]
fn fuzz_pattern_image() {
    fuzz("pattern");
}

#[test]
fn fuzz_design_file() {
    fuzz("design");
}

#[test]
fn fuzz_phase_design() {
    fuzz("phase");
}

#[test]
fn fuzz_sweep_spec() {
    fuzz("spec");
}

#[test]
fn fuzz_spectral_csv() {
    fuzz("spectral");
}

#[test]
fn fuzz_sweep_folder() {
    fuzz("sweep");
}

/// The corpus file a child process replays (see [`fuzz_corpus_replays`]).
const REPLAY_VAR: &str = "UDC_FUZZ_REPLAY";

/// Every crash the fuzzing found, kept as a file named `<reader>-<what>.<ext>`: each must now
/// satisfy the property. Each file is read in a process of its own: a process's peak address
/// space only grows, so one file's large allocation would hide the next one's.
#[test]
fn fuzz_corpus_replays() {
    let dir = repo("tests/corpus/fuzz");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("tests/corpus/fuzz is committed")
        .map(|e| e.expect("entry").path())
        .collect();
    files.sort();
    let exe = std::env::current_exe().expect("the test binary");
    let replay = |path: &Path| {
        std::process::Command::new(&exe)
            .args(["--exact", "fuzz::fuzz_corpus_replay_one", "--nocapture"])
            .env(REPLAY_VAR, path)
            .env("RUST_BACKTRACE", "0")
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("run the test binary")
    };
    let parallel = std::thread::available_parallelism().map_or(2, usize::from);
    let mut failures = Vec::new();
    for batch in files.chunks(parallel) {
        let children: Vec<_> = batch.iter().map(|p| (p, replay(p))).collect();
        for (path, child) in children {
            let out = child.wait_with_output().expect("wait for the replay");
            if !out.status.success() {
                let stderr = String::from_utf8_lossy(&out.stderr);
                let why: Vec<&str> = stderr
                    .lines()
                    .map(str::trim)
                    .filter(|l| {
                        !l.is_empty() && !l.contains("panicked at") && !l.starts_with("note:")
                    })
                    .collect();
                failures.push(format!("{}: {}", path.display(), why.join(" ")));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Replays the corpus file named by `UDC_FUZZ_REPLAY`, alone in this process; without it, as
/// in a plain run of the suite, there is nothing to do.
#[test]
fn fuzz_corpus_replay_one() {
    let Some(path) = std::env::var_os(REPLAY_VAR).map(PathBuf::from) else {
        return;
    };
    let name = path
        .file_name()
        .expect("name")
        .to_string_lossy()
        .into_owned();
    let kind = name.split('-').next().unwrap_or_default();
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_default();
    let bytes = std::fs::read(&path).expect("read a corpus file");
    let work = tempfile::tempdir().expect("temp dir");
    if let Err(f) = check(
        kind,
        &reader(kind),
        work.path(),
        &destination(kind, &ext),
        &bytes,
    ) {
        panic!("{}", f.message);
    }
}
