//! The job layer's own pieces: the flag behind a core setting (`jobs::flags`) and the denoise
//! flags' resolution (`jobs::denoise`). They live in the suite so that the CLI crate needs
//! no unit-test binary of its own (a second compilation of the whole crate).

use udc_studio::core::restore::{Denoise, Recipe, Sigma2};
use udc_studio::core::{Setting, SimError};
use udc_studio::jobs::denoise::{DenoiseFlags, DenoiseMethod, Sigma2Arg};
use udc_studio::jobs::flags::{flag_of, name_flags};

#[test]
fn a_field_only_a_flag_sets_is_reported_by_its_flag() {
    let e = name_flags(SimError::invalid(Setting::ViewingDistanceMm, "must be above 0").into());
    assert_eq!(e.to_string(), "--viewing-distance-mm: must be above 0");
    let e = name_flags(SimError::invalid(Setting::OpeningCells, "too many").into());
    assert_eq!(e.to_string(), "field `opening.cells`: too many");
    // A path is not a setting, even where it spells one: only the core's typed key counts.
    let e = name_flags(SimError::invalid("nsr", "must be ≥ 0").into());
    assert_eq!(e.to_string(), "field `nsr`: must be ≥ 0");
    let e = name_flags(anyhow::anyhow!("not a core error"));
    assert_eq!(e.to_string(), "not a core error");
}

#[test]
fn every_flag_in_the_table_exists_on_some_command() {
    use clap::CommandFactory;
    fn longs(c: &clap::Command, out: &mut Vec<String>) {
        out.extend(
            c.get_arguments()
                .filter_map(|a| a.get_long())
                .map(|l| format!("--{l}")),
        );
        for sub in c.get_subcommands() {
            longs(sub, out);
        }
    }
    let mut all = Vec::new();
    longs(&udc_studio::cli::Cli::command(), &mut all);
    for setting in Setting::ALL {
        if let Some(flag) = flag_of(setting) {
            assert!(
                all.iter().any(|l| l == flag),
                "{setting} → {flag}: no such flag"
            );
        }
    }
}

fn flags(denoise: DenoiseMethod, sigma2: Option<f64>) -> DenoiseFlags {
    DenoiseFlags {
        denoise,
        denoise_sigma2: sigma2.map(Sigma2Arg::Value),
    }
}

#[test]
fn the_default_is_matched_table_names_the_recipe_and_an_override_is_fixed() {
    let d = flags(DenoiseMethod::Bm3d, None).resolve(Recipe::Iccv23);
    assert_eq!(
        d.ok(),
        Some(Denoise::Bm3d {
            sigma2: Sigma2::Matched
        })
    );
    for recipe in [Recipe::Iccp21, Recipe::Iccv23] {
        let d = DenoiseFlags {
            denoise: DenoiseMethod::Bm3d,
            denoise_sigma2: Some(Sigma2Arg::Table),
        }
        .resolve(recipe);
        assert_eq!(d.ok(), Some(Denoise::authors_table(recipe)));
    }
    let d = flags(DenoiseMethod::Bm3d, Some(0.003)).resolve(Recipe::Iccp21);
    assert_eq!(
        d.ok(),
        Some(Denoise::Bm3d {
            sigma2: Sigma2::Fixed(0.003)
        })
    );
    let d = flags(DenoiseMethod::None, None).resolve(Recipe::Iccp21);
    assert_eq!(d.ok(), Some(Denoise::None));
}

/// `--denoise-sigma2` reads `matched` or `table` (any case) or a number, and nothing else.
#[test]
fn sigma2_reads_matched_table_or_a_number() {
    assert_eq!("matched".parse(), Ok(Sigma2Arg::Matched));
    assert_eq!("MATCHED".parse(), Ok(Sigma2Arg::Matched));
    assert_eq!("Table".parse(), Ok(Sigma2Arg::Table));
    assert_eq!("0.002".parse(), Ok(Sigma2Arg::Value(0.002)));
    let bad: Result<Sigma2Arg, _> = "match".parse();
    assert!(bad.is_err_and(|e| e.contains("neither `matched`, `table` nor a number")));
    let d = DenoiseFlags {
        denoise: DenoiseMethod::Bm3d,
        denoise_sigma2: Some(Sigma2Arg::Matched),
    }
    .resolve(Recipe::Iccv23);
    assert_eq!(
        d.ok(),
        Some(Denoise::Bm3d {
            sigma2: Sigma2::Matched
        })
    );
    let none = DenoiseFlags {
        denoise: DenoiseMethod::None,
        denoise_sigma2: Some(Sigma2Arg::Matched),
    }
    .resolve(Recipe::Iccv23);
    assert!(none.is_err(), "matched σ² with no denoiser");
}

#[test]
fn bad_values_are_one_line_errors() {
    for (f, needle) in [
        (flags(DenoiseMethod::Bm3d, Some(0.0)), "finite number > 0"),
        (flags(DenoiseMethod::Bm3d, Some(-0.01)), "finite number > 0"),
        (flags(DenoiseMethod::Bm3d, Some(1e308)), "at most 1"),
        (flags(DenoiseMethod::Bm3d, Some(1e-300)), "at least 1e-12"),
        (
            flags(DenoiseMethod::Bm3d, Some(f64::NAN)),
            "finite number > 0",
        ),
        (flags(DenoiseMethod::None, Some(0.002)), "--denoise none"),
    ] {
        let msg = f
            .resolve(Recipe::Iccp21)
            .err()
            .map(|e| format!("{e:#}"))
            .unwrap_or_default();
        assert!(msg.contains(needle), "{msg}");
        assert!(msg.contains("--denoise-sigma2"), "{msg}");
        assert!(!msg.contains('\n'), "{msg}");
    }
}
