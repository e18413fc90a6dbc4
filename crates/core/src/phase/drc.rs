//! The design-rule check of a phase plate: every stretch between two height jumps (a fold ring,
//! or a quantised height step) against the narrowest feature its writer can make.
//! The features are [`super::plate::features`]: pieces joined where the height runs on across
//! a lenslet edge.

use super::PhaseDesign;
use super::geometry::Lenslets;
use super::plate::{Feature, features, pieces};
use crate::SimError;
use crate::mask::drc::{DrcReport, Rules, Violation, ViolationKind};

/// Checks the plate of `design` against `rules.phase_min_feature_um`. The report has the same
/// shape as a display mask's: its smallest feature, and each violation with where it is (x in
/// µm in the plate's frame, y 0) and, in words, its lenslet and radius.
///
/// # Errors
/// As [`super::plate::pieces`]: a plan that does not fit, or a profile too finely cut.
pub fn check_plate(design: &PhaseDesign, rules: &Rules) -> Result<DrcReport, SimError> {
    let lenslets = Lenslets::new(design)?;
    let rule = rules.phase_min_feature_um;
    let features = features(design, &pieces(design, &lenslets, rule)?);
    let mut report = DrcReport::new(*rules);
    for f in &features {
        let width = f.width_um();
        report.min_feature_um = Some(report.min_feature_um.map_or(width, |m| m.min(width)));
        if width < rule - 1e-12 {
            report.push(Violation {
                kind: ViolationKind::MinFeature,
                value: width,
                at_um: [f.x0_um, 0.0],
                place: place(&lenslets, f),
            });
        }
    }
    Ok(report)
}

/// Where `f` is, in words: its lenslet, the radii it spans and on which side of the centre.
fn place(lenslets: &Lenslets, f: &Feature) -> String {
    let mid = 0.5 * (f.x0_um + f.x1_um);
    let Some((l, u)) = lenslets.locate(mid) else {
        return format!("x = {:.3} µm", f.x0_um);
    };
    let c = lenslets.centre_um(l);
    let (r0, r1) = ((f.x0_um - c).abs(), (f.x1_um - c).abs());
    let (inner, outer) = (r0.min(r1), r0.max(r1));
    if outer > 0.5 * lenslets.pitch_um + 1e-9 {
        let other = if u < 0.0 { l.saturating_sub(1) } else { l + 1 };
        return format!(
            "lenslets {}-{}, across their edge at x = {:.3} µm",
            l.min(other),
            l.max(other),
            f.x0_um
        );
    }
    let side = if f.x1_um <= c + 1e-9 {
        "left of its centre"
    } else if f.x0_um >= c - 1e-9 {
        "right of its centre"
    } else {
        "across its centre"
    };
    format!("lenslet {l}, ring at r = {inner:.3}-{outer:.3} µm, {side}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_thesis_plate_breaks_a_half_micron_rule_near_the_lenslet_edges() {
        let mut d = PhaseDesign::thesis(168.0, 1.0);
        d.height_step_um = Some(0.2);
        let r = check_plate(&d, &Rules::default()).unwrap();
        let min = r.min_feature_um.unwrap();
        assert!(min > 0.0 && min < 0.2, "{min}");
        assert!(!r.is_clean());
        let v = &r.violations[0];
        assert_eq!(v.kind, ViolationKind::MinFeature);
        assert!(v.place.starts_with("lenslet"), "{}", v.place);
        // A rule of 0 is not checked.
        let off = Rules {
            phase_min_feature_um: 0.0,
            ..Rules::default()
        };
        assert!(check_plate(&d, &off).unwrap().is_clean());
    }

    #[test]
    fn pieces_without_a_jump_between_them_are_one_feature() {
        let d = PhaseDesign::thesis(42.0, 1.0);
        let lenslets = Lenslets::new(&d).unwrap();
        let p = pieces(&d, &lenslets, 0.5).unwrap();
        let f = features(&d, &p);
        assert!(f.len() <= p.len());
        let span = |v: &[Feature]| v.iter().map(|f| f.x1_um - f.x0_um).sum::<f64>();
        let pieces_span: f64 = p.iter().map(|p| p.x1_um - p.x0_um).sum();
        assert!((span(&f) - pieces_span).abs() < 1e-6);
    }
}
