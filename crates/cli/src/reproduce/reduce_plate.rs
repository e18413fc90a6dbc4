//! Chapter 4's plate: Table 4.2 (the order of the folding heights) and Fig. 4.10 (pitch and
//! height steps), from `phase restore` sweeps.

use super::outcome::{Claim, Outcome, ReportRow, SweepTable, Value, fmt, fmt_signed};
use super::thesis;

/// Table 4.2 from the `phase` part.
pub fn table4_2(t: &SweepTable) -> Outcome {
    let mut out = Outcome::default();
    let at = |plan: &str, order: &str, m: &str| {
        t.mean(
            &format!("runs.0.{m}"),
            &[("lambda0", plan), ("order", order)],
        )
    };
    let mut deltas = Vec::new();
    for (k, plan) in ["uniform", "optimized"].iter().enumerate() {
        for (order, name) in [("ascending", "ordered"), ("shuffled", "shuffled")] {
            let label = format!("{plan}, {name}");
            let th = thesis::TABLE_4_2.iter().find(|r| r.setup == label);
            let psnr = at(plan, order, "psnr_db");
            let ssim = at(plan, order, "ssim");
            let mut values = vec![
                Value::psnr(psnr, th.and_then(|r| r.psnr_db)),
                Value::ssim(ssim, th.and_then(|r| r.ssim)),
            ];
            let mut note = format!(
                "{} dB from the thesis: the phase model with BM3D and CG on our photos, not its \
                 30 (absolute values differ, the orderings compare)",
                fmt_signed(psnr.zip(th.and_then(|r| r.psnr_db)).map(|(a, b)| a - b), 2)
            );
            if order == "shuffled" {
                let base_p = at(plan, "ascending", "psnr_db");
                let base_s = at(plan, "ascending", "ssim");
                let dp = psnr.zip(base_p).map(|(a, b)| 100.0 * (a - b) / b);
                let ds = ssim.zip(base_s).map(|(a, b)| 100.0 * (a - b) / b);
                deltas.push((*plan, dp, thesis::TABLE_4_2_DELTA_PSNR_PERCENT[k]));
                values.push(Value::both(
                    "delta_psnr_percent",
                    "ΔPSNR (%)",
                    dp,
                    Some(thesis::TABLE_4_2_DELTA_PSNR_PERCENT[k]),
                    2,
                ));
                values.push(Value::both(
                    "delta_ssim_percent",
                    "ΔSSIM (%)",
                    ds,
                    Some(thesis::TABLE_4_2_DELTA_SSIM_PERCENT[k]),
                    2,
                ));
                note = format!(
                    "shuffling costs {} % of PSNR against the thesis's {:.2} %: {}",
                    fmt(dp.map(f64::abs), 2),
                    thesis::TABLE_4_2_DELTA_PSNR_PERCENT[k].abs(),
                    if dp.is_some_and(|d| d.abs() > thesis::TABLE_4_2_NEGLIGIBLE_PERCENT) {
                        "neighbouring lenslets folded at different λ0 step in height at their \
                         joins, and a shuffled plate has more and larger steps, which scatter \
                         light out of the lens"
                    } else {
                        "negligible, as the thesis finds"
                    }
                );
            } else {
                values.push(Value::both(
                    "delta_psnr_percent",
                    "ΔPSNR (%)",
                    None,
                    None,
                    2,
                ));
                values.push(Value::both(
                    "delta_ssim_percent",
                    "ΔSSIM (%)",
                    None,
                    None,
                    2,
                ));
            }
            out.rows.push(ReportRow {
                setup: label,
                values,
                thesis_claim: None,
                note,
            });
        }
    }
    for (plan, dp, want) in &deltas {
        let cost = dp.map(|d| -d);
        let pass = cost.is_some_and(|c| c < thesis::TABLE_4_2_NEGLIGIBLE_PERCENT);
        out.claims.push(Claim {
            claim: format!(
                "{plan} λ0: shuffling the order costs less than {} % of PSNR (thesis {want:+.2} %)",
                thesis::TABLE_4_2_NEGLIGIBLE_PERCENT
            ),
            measured: format!("{} %", fmt_signed(*dp, 2)),
            pass,
            why: if pass {
                "the order of the folding heights hardly matters, as §4.5 says".into()
            } else {
                format!(
                    "{} percentage points more than the thesis's 1 %: in this model each \
                     lenslet is folded on its own centred coordinate, so where neighbours have \
                     different λ0 the plate steps by mod(S, d_l) − mod(S, d_l+1) at their joint \
                     (conventions.md §7); a shuffled plate has larger steps between lenslets, \
                     which scatter light out of the lens (its LTR drops) and into directions V \
                     does not score. The thesis reports one unpublished realisation (30 photos, \
                     tuned BM3D) and does not say how its plate joins lenslets",
                    fmt(cost.map(|c| c - thesis::TABLE_4_2_NEGLIGIBLE_PERCENT), 2)
                )
            },
        });
    }
    let better = |order: &str, m: &str| {
        matches!(
            (at("optimized", order, m), at("uniform", order, m)),
            (Some(o), Some(u)) if o > u
        )
    };
    out.claims.push(Claim {
        claim: "optimized λ0 outperform uniform λ0, ordered and shuffled (thesis: by 0.75 and \
                0.67 dB)"
            .into(),
        measured: format!(
            "ordered {} vs {} dB, shuffled {} vs {} dB",
            fmt(at("optimized", "ascending", "psnr_db"), 2),
            fmt(at("uniform", "ascending", "psnr_db"), 2),
            fmt(at("optimized", "shuffled", "psnr_db"), 2),
            fmt(at("uniform", "shuffled", "psnr_db"), 2)
        ),
        pass: better("ascending", "psnr_db") && better("shuffled", "psnr_db"),
        why: "Algorithm 1 balances the three channels' invertibility; uniform λ0 spends lenslets \
              on wavelengths the sensor barely sees"
            .into(),
    });
    out.notes.push(format!(
        "Source: {}. `phase restore` at T = 1, 600 DPI, 1600 photons, the thesis's sampling; the \
         shuffled plates permute the same λ0 list with seed 1 (the same seed draws the noise).",
        thesis::TABLE_4_2_SOURCE
    ));
    out
}

/// Fig. 4.10's setups (the `setup` axis's names).
const FIG_4_10_SETUPS: [&str; 4] = [
    "TOLED",
    "T=1 optimized",
    "T=5 optimized",
    "T=5 optimized, 0.2 um steps",
];

/// Fig. 4.10 from the `phase` part.
pub fn fig4_10(t: &SweepTable) -> Outcome {
    let mut out = Outcome::default();
    let pitches = t.values_of("pitch-um");
    let dpi = |p: &str| p.parse::<f64>().map_or(f64::NAN, |p| 25400.0 / p);
    let at = |setup: &str, p: &str, m: &str| {
        t.mean(&format!("runs.0.{m}"), &[("setup", setup), ("pitch-um", p)])
    };
    for setup in FIG_4_10_SETUPS {
        for p in &pitches {
            out.rows.push(ReportRow {
                setup: format!("{setup}, {p} µm ({:.0} DPI)", dpi(p)),
                values: vec![
                    Value::psnr(at(setup, p, "psnr_db"), None),
                    Value::ssim(at(setup, p, "ssim"), None),
                ],
                thesis_claim: Some("plotted only (Fig. 4.10); see the claims".into()),
                note: "the thesis plots this point at 1600 photons".into(),
            });
        }
    }
    let margin = |setup: &str, p: &str| Some(at(setup, p, "psnr_db")? - at("TOLED", p, "psnr_db")?);
    let list = |setup: &str, ps: &[String]| {
        ps.iter()
            .map(|p| format!("{p} µm {} dB", fmt_signed(margin(setup, p), 2)))
            .collect::<Vec<_>>()
            .join(", ")
    };
    out.claims.push(Claim {
        claim: thesis::FIG_4_10_CLAIMS[0].into(),
        measured: list("T=5 optimized", &pitches),
        pass: !pitches.is_empty()
            && pitches
                .iter()
                .all(|p| margin("T=5 optimized", p).is_some_and(|m| m > 0.0)),
        why: "a 5 µm fold wraps the lenslets rarely, so they act nearly as thick lenses".into(),
    });
    let fine: Vec<String> = pitches.iter().filter(|p| dpi(p) > 301.0).cloned().collect();
    out.claims.push(Claim {
        claim: thesis::FIG_4_10_CLAIMS[1].into(),
        measured: format!(
            "above 300 DPI: {}; at and below: {}",
            list("T=1 optimized", &fine),
            list(
                "T=1 optimized",
                &pitches
                    .iter()
                    .filter(|p| dpi(p) <= 301.0)
                    .cloned()
                    .collect::<Vec<_>>()
            )
        ),
        pass: !fine.is_empty()
            && fine
                .iter()
                .all(|p| margin("T=1 optimized", p).is_some_and(|m| m > 0.0)),
        why: "larger lenslets (coarser pitch) wrap more often in a 1 µm plate, and the wraps \
              scatter"
            .into(),
    });
    let q_tol = (0.5, 0.01);
    let steps: Vec<(String, Option<f64>, Option<f64>)> = pitches
        .iter()
        .map(|p| {
            let dp = Some(
                at("T=5 optimized, 0.2 um steps", p, "psnr_db")?
                    - at("T=5 optimized", p, "psnr_db")?,
            );
            let ds = Some(
                at("T=5 optimized, 0.2 um steps", p, "ssim")? - at("T=5 optimized", p, "ssim")?,
            );
            Some((p.clone(), dp, ds))
        })
        .map(|x| x.unwrap_or_default())
        .collect();
    out.claims.push(Claim {
        claim: format!(
            "{} (checked as within {} dB and {} SSIM of the unquantized T = 5 plate)",
            thesis::FIG_4_10_CLAIMS[2],
            q_tol.0,
            q_tol.1
        ),
        measured: steps
            .iter()
            .map(|(p, dp, ds)| format!("{p} µm {} dB / {}", fmt_signed(*dp, 2), fmt_signed(*ds, 3)))
            .collect::<Vec<_>>()
            .join(", "),
        pass: !steps.is_empty()
            && steps.iter().all(|(_, dp, ds)| {
                dp.is_some_and(|d| d.abs() <= q_tol.0) && ds.is_some_and(|d| d.abs() <= q_tol.1)
            }),
        why: format!(
            "flooring to 0.2 µm shifts the phase by at most 0.2·(n − 1)/λ0 ≈ 0.2 waves, which \
             moves little light; measured, the floored plate passes {} of the unquantized \
             plate's light (LTR), so its capture is that much noisier at the same photons, \
             which SSIM feels first",
            pitches
                .iter()
                .map(|p| {
                    let ltr = |setup: &str| t.mean("ltr", &[("setup", setup), ("pitch-um", p)]);
                    let kept = ltr("T=5 optimized, 0.2 um steps")
                        .zip(ltr("T=5 optimized"))
                        .map(|(q, u)| 100.0 * q / u);
                    format!("{} % at {p} µm", fmt(kept, 1))
                })
                .collect::<Vec<_>>()
                .join(", ")
        ),
    });
    out.notes.push(
        "`phase restore` at 1600 photons, the chapter-4 camera and the thesis's sampling; the \
         pitch sets the lenslets' focal length (κ = 4.2 at every pitch). The 0.2 µm steps floor \
         the heights as the authors' code does."
            .into(),
    );
    out
}
