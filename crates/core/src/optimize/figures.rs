//! The optimizer's losses per epoch as a figure: L_inv, the grey mask's mean, the area
//! target and (with a photo) L_data, with the start design and the result scored alike as
//! points at both ends.

use super::{EpochReport, Scores};
use crate::figure::{Axis, Mark, Panel, Series, palette};

/// The losses of `history` against the epoch (1-based); `scores`, once the run has finished,
/// adds L_inv of the start design at epoch 0 and of the result after the last epoch.
pub fn losses_panel(history: &[EpochReport], scores: Option<&Scores>) -> Panel {
    let pts = |f: &dyn Fn(&EpochReport) -> f64| -> Vec<[f64; 2]> {
        history
            .iter()
            .map(|r| [(r.epoch + 1) as f64, f(r)])
            .collect()
    };
    let mut out = vec![
        Series::new(
            "L_inv",
            palette::series(0),
            Mark::Line,
            pts(&|r| r.loss_inv),
        ),
        Series::new(
            "grey-mask mean",
            palette::REFERENCE,
            Mark::Line,
            pts(&|r| r.open_fraction),
        ),
        Series::new(
            "area target",
            palette::series(4),
            Mark::Line,
            pts(&|r| r.area_target),
        ),
    ];
    if history.iter().any(|r| r.loss_data.is_some()) {
        out.push(Series::new(
            "L_data",
            palette::series(3),
            Mark::Line,
            pts(&|r| r.loss_data.unwrap_or(0.0)),
        ));
    }
    if let Some(s) = scores {
        if let Some(start) = s.start {
            out.push(Series::new(
                "L_inv of the start design",
                palette::series(1),
                Mark::Points,
                vec![[0.0, start.loss_inv]],
            ));
        }
        out.push(Series::new(
            "L_inv of the result",
            palette::series(2),
            Mark::Points,
            vec![[history.len() as f64, s.result.loss_inv]],
        ));
    }
    Panel {
        title: "Losses per epoch".into(),
        x: Axis::new("epoch", None),
        y: Axis::new("value (no unit)", None),
        series: out,
        ..Panel::default()
    }
}
