//! The thesis results `reproduce` knows: what each runs (its sweep specs in
//! `presets/reproduce/`), what it checks, what it costs, and how `--quick` trims it.

use std::path::PathBuf;

use crate::sweep::ParamValue;

/// A thesis result.
#[derive(strum::VariantArray, strum::IntoStaticStr, strum::EnumMessage, strum::Display)]
#[strum(serialize_all = "kebab-case")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ResultId {
    /// Fig. 3.8: six display layouts at five light levels.
    #[strum(serialize = "fig3.8")]
    Fig3_8,
    /// Fig. 3.9: pixel density.
    #[strum(serialize = "fig3.9")]
    Fig3_9,
    /// Table 4.1: the double MLA against other OLED displays.
    #[strum(serialize = "table4.1")]
    Table4_1,
    /// Table 4.2: the order of the folding wavelengths.
    #[strum(serialize = "table4.2")]
    Table4_2,
    /// Fig. 4.10: pitch and height quantisation of the phase masks.
    #[strum(serialize = "fig4.10")]
    Fig4_10,
    /// Fig. 4.14: the displays of Table 4.1 over light levels.
    #[strum(serialize = "fig4.14")]
    Fig4_14,
    /// Table 5.1: the binning modes' variances.
    #[strum(serialize = "table5.1")]
    Table5_1,
    /// Table 5.4: the sensor strategies' worst-ROI SSIM.
    #[strum(serialize = "table5.4")]
    Table5_4,
}

/// A value a quick plan sets in a spec's base.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum QuickValue {
    /// A switch.
    Switch(bool),
    /// A number.
    Number(f64),
    /// A word.
    Word(&'static str),
}

impl QuickValue {
    /// As a spec value.
    pub fn to_param(self) -> ParamValue {
        match self {
            QuickValue::Switch(b) => ParamValue::Bool(b),
            QuickValue::Number(x) if x.fract() == 0.0 && x.abs() < 1e15 => {
                ParamValue::Int(x as i64)
            }
            QuickValue::Number(x) => ParamValue::Float(x),
            QuickValue::Word(w) => ParamValue::Text(w.to_string()),
        }
    }
}

/// How `--quick` trims a part: axis values kept, base values set, photos used (at 256²).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuickPlan {
    /// Axes cut to these values (as the command line spells them).
    pub keep: &'static [(&'static str, &'static [&'static str])],
    /// Base parameters set (e.g. the phase model's preview sampling).
    pub set: &'static [(&'static str, QuickValue)],
    /// The photos kept, by file stem, scaled to 256²; empty leaves the inputs alone.
    pub photos: &'static [&'static str],
}

/// One sweep of a result: its spec file and how `--quick` trims it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Part {
    /// A short name (`phase`, `display`): the sweep's folder and its plots' prefix.
    pub name: &'static str,
    /// The spec, in `presets/reproduce/`.
    pub file: &'static str,
    /// The axis of input photos or scenes, listed in the report.
    pub inputs: Option<&'static str>,
    /// Whether the sweep's own plots are drawn (a phase part whose light levels are runs
    /// within a point has none worth drawing; the result draws its curves instead).
    pub plots: bool,
    /// The quick plan.
    pub quick: QuickPlan,
}

/// The three photos of every quick run: natural colour photos of the test set.
pub const QUICK_PHOTOS: &[&str] = &["astronaut", "chelsea", "coffee"];

const NO_QUICK_CHANGE: QuickPlan = QuickPlan {
    keep: &[],
    set: &[],
    photos: &[],
};

/// The phase model on its preview sampling (60 nm at the display, 7 samples per pixel) with
/// the full spectral response: ~5 s per setup and photo on 2 cores instead of ~30 s, within
/// 0.1 dB of the thesis sampling on Table 4.1's setups. (The peak wavelengths alone would be
/// as fast but flatter a plate folded at 530 nm by 6 dB.)
const PREVIEW: (&str, QuickValue) = ("preview", QuickValue::Switch(true));

/// Table 4.1's and Fig. 4.14's phase-model rows.
const TABLE_4_1_PHASE: Part = Part {
    name: "phase",
    file: "table4.1.toml",
    inputs: Some("photo"),
    plots: false,
    quick: QuickPlan {
        keep: &[],
        set: &[PREVIEW],
        photos: QUICK_PHOTOS,
    },
};

/// The geometry of the phase model's photos: ours (each photo as it is, its own width of
/// directions on as many sensor pixels, restored on the same columns) or the thesis's (§4.4.1:
/// every photo scaled to the sensor's 1024 columns, restored with a 'full' boundary, that is on
/// twice as many columns, and cropped back).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Geometry {
    /// Each photo its own width, a closed world.
    #[default]
    Ours,
    /// Thesis §4.4.1: 1024 columns, 'full' boundary.
    Thesis,
}

/// Table 4.1's and Fig. 4.14's phase-model rows in the thesis's geometry (its own spec, which
/// `sweep slurm` runs on a cluster as it stands).
const TABLE_4_1_PHASE_THESIS_GEOMETRY: Part = Part {
    name: "phase",
    file: "table4.1.thesis-geometry.toml",
    inputs: Some("photo"),
    plots: false,
    quick: TABLE_4_1_PHASE.quick,
};

/// Table 4.1's and Fig. 4.14's 2-D layouts.
const TABLE_4_1_DISPLAY: Part = Part {
    name: "display",
    file: "table4.1.display.toml",
    inputs: Some("image"),
    plots: true,
    quick: QuickPlan {
        // The 2-D T-OLED is a cross-check, not a thesis row.
        keep: &[("display", &["POLED", "Yang et al."])],
        set: &[],
        photos: QUICK_PHOTOS,
    },
};

/// The dim 2-D layouts again, BM3D told the authors' σ² table (chapter 4's: the noise of a
/// display that passes all the light, conventions.md §5) instead of each capture's own noise.
const TABLE_4_1_DISPLAY_TABLE: Part = Part {
    name: "display-table",
    file: "table4.1.display-table.toml",
    inputs: Some("image"),
    plots: false,
    quick: QuickPlan {
        keep: &[],
        set: &[],
        photos: QUICK_PHOTOS,
    },
};

impl ResultId {
    /// Every result, in the thesis's order.
    pub const ALL: [ResultId; 8] = [
        ResultId::Fig3_8,
        ResultId::Fig3_9,
        ResultId::Table4_1,
        ResultId::Table4_2,
        ResultId::Fig4_10,
        ResultId::Fig4_14,
        ResultId::Table5_1,
        ResultId::Table5_4,
    ];

    /// The ID on the command line (`fig3.8`).
    pub fn as_str(self) -> &'static str {
        self.into()
    }

    /// The result's title.
    pub fn title(self) -> &'static str {
        match self {
            ResultId::Fig3_8 => "Fig. 3.8: random tiling and optimized openings, five light levels",
            ResultId::Fig3_9 => "Fig. 3.9: display pixel density (80–300 DPI) at SNR 32 dB",
            ResultId::Table4_1 => "Table 4.1: the double MLA against other OLED displays",
            ResultId::Table4_2 => "Table 4.2: ordered against shuffled folding heights",
            ResultId::Fig4_10 => "Fig. 4.10: phase masks over pixel pitch, and 0.2 µm steps",
            ResultId::Fig4_14 => "Fig. 4.14: the displays of Table 4.1 over light levels",
            ResultId::Table5_1 => "Table 5.1: noise variance of the binning modes",
            ResultId::Table5_4 => "Table 5.4: worst-ROI SSIM of the sensor strategies",
        }
    }

    /// What it runs, one sentence.
    pub fn runs(self) -> &'static str {
        match self {
            ResultId::Fig3_8 => {
                "`restore` (BM3D then Wiener, iccp21 camera, 150 DPI) through T-OLED, top-10 L2 \
                 and top-10 L2 + inv, each periodic and random, at SNR 24/28/32/36/40 dB"
            }
            ResultId::Fig3_9 => {
                "`restore` (BM3D then Wiener, SNR 32 dB) through T-OLED, P-OLED and L2 + inv \
                 (periodic, random) at 80, 100, 150, 200 and 300 DPI"
            }
            ResultId::Table4_1 => {
                "`phase restore` (bare T-OLED and the T = 5 optimized double MLA, 600 DPI) and \
                 `restore` with the chapter-4 camera and CG (P-OLED, the chapter-3 optimized \
                 random layout as Yang et al., and a 2-D T-OLED), 250–10 000 photons, BM3D told \
                 each capture's own noise; P-OLED and Yang et al. again with the authors' σ² table"
            }
            ResultId::Table4_2 => {
                "`phase restore` at T = 1, 1600 photons: uniform and optimized λ0, ascending \
                 and shuffled"
            }
            ResultId::Fig4_10 => {
                "`phase restore` at 1600 photons: bare T-OLED and optimized double MLAs \
                 (T = 1, T = 5) at 42/56/84/168 µm, and T = 5 with 0.2 µm height steps"
            }
            ResultId::Fig4_14 => {
                "the runs of Table 4.1 at each light level (250, 650, 1600, 10 000 photons)"
            }
            ResultId::Table5_1 => {
                "`sensor flat-patch` Monte Carlo: a flat patch read without binning and in \
                 2×2 and 4×4 bins (additive at ĝ = g/N and ĝ = g, average, digital)"
            }
            ResultId::Table5_4 => {
                "`sensor` (Table 5.4's sensor) on the shipped HDR scenes: const/vary gain × \
                 no/vary bin, worst-ROI SSIM"
            }
        }
    }

    /// The thesis numbers (or claims) it checks.
    pub fn checks(self) -> &'static str {
        match self {
            ResultId::Fig3_8 => {
                "random beats periodic for every opening at every light level; L2 + inv random \
                 beats T-OLED by > 6 dB (thesis: > 8 dB, 0.11 SSIM)"
            }
            ResultId::Fig3_9 => {
                "quality falls with DPI; the optimized layouts beat T-OLED and P-OLED at every \
                 DPI; the gain over P-OLED is the smaller"
            }
            ResultId::Table4_1 => {
                "PSNR/SSIM/LTR of T-OLED 22.42/0.59, P-OLED 26.22/0.67, ours 28.01/0.75, Yang \
                 et al. 32.93/0.88 (±2.5 dB); ours > P-OLED > T-OLED; margin 5.6 ± 1.5 dB"
            }
            ResultId::Table4_2 => {
                "26.69/0.7106, 26.51/0.7187, 27.44/0.7368, 27.18/0.7396; shuffling costs < 1 % \
                 PSNR; optimized beats uniform"
            }
            ResultId::Fig4_10 => {
                "T = 5 beats T-OLED at all four pitches; T = 1 beats it above 300 DPI; 0.2 µm \
                 steps perform similarly"
            }
            ResultId::Fig4_14 => {
                "ours beats T-OLED at every light level; P-OLED ~10 dB below ours at 250 \
                 photons, rising fast with light"
            }
            ResultId::Table5_1 => {
                "each mode's measured variance equals Table 5.1's formula; digital < average = \
                 additive (ĝ = g/N); additive at ĝ = g lowest"
            }
            ResultId::Table5_4 => {
                "average worst-ROI SSIM 0.18/0.30/0.28/0.39: vary/vary best, const/no-bin worst"
            }
        }
    }

    /// Estimated wall time on 2 cores (release build): quick, full.
    pub fn cost(self) -> (&'static str, &'static str) {
        match self {
            ResultId::Fig3_8 => ("≈ 1 min", "≈ 15 min"),
            ResultId::Fig3_9 => ("≈ 1 min", "≈ 10 min"),
            ResultId::Table4_1 => ("≈ 1 min", "≈ 3.5 h"),
            ResultId::Table4_2 => ("≈ 1 min", "≈ 2 h"),
            ResultId::Fig4_10 => ("≈ 1.5 min", "≈ 5 h"),
            ResultId::Fig4_14 => ("≈ 1 min", "≈ 3 h"),
            ResultId::Table5_1 => ("≈ 2 s", "≈ 10 s"),
            ResultId::Table5_4 => ("≈ 5 s", "≈ 30 s"),
        }
    }

    /// Whether `geometry` changes this result (the thesis's geometry is the phase model's).
    pub fn has_geometry(self, geometry: Geometry) -> bool {
        geometry == Geometry::Ours || matches!(self, ResultId::Table4_1 | ResultId::Fig4_14)
    }

    /// Its sweeps in `geometry` (the phase rows of Table 4.1 and Fig. 4.14 change; every other
    /// part is the same in both).
    pub fn parts_for(self, geometry: Geometry) -> &'static [Part] {
        match (self, geometry) {
            (ResultId::Table4_1, Geometry::Thesis) => &[
                TABLE_4_1_PHASE_THESIS_GEOMETRY,
                TABLE_4_1_DISPLAY,
                TABLE_4_1_DISPLAY_TABLE,
            ],
            (ResultId::Fig4_14, Geometry::Thesis) => {
                &[TABLE_4_1_PHASE_THESIS_GEOMETRY, TABLE_4_1_DISPLAY]
            }
            _ => self.parts(),
        }
    }

    /// Its sweeps.
    pub fn parts(self) -> &'static [Part] {
        match self {
            ResultId::Fig3_8 => &[Part {
                name: "display",
                file: "fig3.8.toml",
                inputs: Some("image"),
                plots: true,
                quick: QuickPlan {
                    keep: &[],
                    set: &[],
                    photos: QUICK_PHOTOS,
                },
            }],
            ResultId::Fig3_9 => &[Part {
                name: "display",
                file: "fig3.9.toml",
                inputs: Some("image"),
                plots: true,
                quick: QuickPlan {
                    keep: &[],
                    set: &[],
                    photos: QUICK_PHOTOS,
                },
            }],
            ResultId::Table4_1 => &[TABLE_4_1_PHASE, TABLE_4_1_DISPLAY, TABLE_4_1_DISPLAY_TABLE],
            ResultId::Fig4_14 => &[TABLE_4_1_PHASE, TABLE_4_1_DISPLAY],
            ResultId::Table4_2 => &[Part {
                name: "phase",
                file: "table4.2.toml",
                inputs: Some("photo"),
                plots: true,
                quick: QuickPlan {
                    keep: &[],
                    set: &[PREVIEW],
                    photos: QUICK_PHOTOS,
                },
            }],
            ResultId::Fig4_10 => &[Part {
                name: "phase",
                file: "fig4.10.toml",
                inputs: Some("photo"),
                plots: true,
                quick: QuickPlan {
                    // The densest and the sparsest pitch (605 and 151 DPI): each claim still
                    // has a pitch on both sides of 300 DPI, in half the time of all four.
                    keep: &[("pitch-um", &["42", "168"])],
                    set: &[PREVIEW],
                    photos: QUICK_PHOTOS,
                },
            }],
            ResultId::Table5_1 => &[Part {
                name: "sensor",
                file: "table5.1.toml",
                inputs: None,
                plots: true,
                quick: QuickPlan {
                    keep: &[],
                    set: &[("side-px", QuickValue::Number(256.0))],
                    photos: &[],
                },
            }],
            ResultId::Table5_4 => &[Part {
                name: "sensor",
                file: "table5.4.toml",
                inputs: Some("hdr"),
                plots: true,
                quick: QuickPlan {
                    keep: &[("seed", &["0"])],
                    ..NO_QUICK_CHANGE
                },
            }],
        }
    }

    /// The default results folder, `reproduce/<id>`.
    pub fn default_out(self) -> PathBuf {
        PathBuf::from("reproduce").join(self.as_str())
    }
}
