//! Widgets every workspace uses and none owns: colour maps, photos, the message line.

pub mod colormap;
pub mod denoise;
pub mod figure;
pub mod photo;
pub mod plot;

use crate::app::notice::Notice;

/// A panel's latest message: red when it is an error, dimmed otherwise.
pub fn message_ui(ui: &mut egui::Ui, message: Option<&Notice>) {
    if let Some(n) = message {
        let color = if n.is_error() {
            ui.visuals().error_fg_color
        } else {
            ui.visuals().weak_text_color()
        };
        ui.colored_label(color, &n.text);
    }
}

/// A number field that commits once: typed text reaches the value on Enter or when the field
/// loses focus (typing 168 is one edit, not 1, 16, 168), dragging changes it live, and text that
/// is not a finite number (`nan`, `inf`, `abc`) is refused, keeping the previous value.
pub fn number<Num: egui::emath::Numeric>(value: &mut Num) -> egui::DragValue<'_> {
    egui::DragValue::new(value)
        .update_while_editing(false)
        .custom_parser(parse_finite)
}

/// egui's own number syntax (spaces ignored, `−` as minus), finite values only; a unit after
/// the number ("6 cells", "12 µm", as a formatter shows it) is ignored. Refused text is
/// remembered for [`take_refused`], so the shell can say why the field kept its value.
fn parse_finite(text: &str) -> Option<f64> {
    let number = text.trim_end_matches(|c: char| c.is_alphabetic() || c.is_whitespace());
    let cleaned: String = number
        .chars()
        .filter(|c| !c.is_whitespace())
        .map(|c| if c == '−' { '-' } else { c })
        .collect();
    let value = cleaned.parse::<f64>().ok();
    let reason = match value {
        Some(v) if v.is_finite() => return Some(v),
        Some(_) => "is not a finite number",
        None => "is not a number",
    };
    REFUSED.with(|r| {
        *r.borrow_mut() = Some(format!(
            "\"{}\" {reason}: the field keeps its value",
            text.trim()
        ));
    });
    None
}

thread_local! {
    /// The latest text a number field refused (the UI thread's; each test harness has its own).
    static REFUSED: std::cell::RefCell<Option<String>> = const { std::cell::RefCell::new(None) };
}

/// Why a number field refused what was typed since the last call, if it did.
pub fn take_refused() -> Option<String> {
    REFUSED.with(|r| r.borrow_mut().take())
}

/// `value` with its unit in the right number: "1 cell", "2 cells", "0.5 cells".
pub fn counted(value: f64, one: &str, many: &str) -> String {
    let unit = if value == 1.0 { one } else { many };
    format!(
        "{} {unit}",
        egui::emath::format_with_decimals_in_range(value, 0..=2)
    )
}

#[cfg(test)]
mod tests {
    #[test]
    fn refused_text_says_why() {
        assert_eq!(super::parse_finite("12 µm"), Some(12.0));
        assert_eq!(super::take_refused(), None);
        assert_eq!(super::parse_finite("abc"), None);
        assert_eq!(
            super::take_refused().as_deref(),
            Some("\"abc\" is not a number: the field keeps its value")
        );
        assert_eq!(super::parse_finite("1e400"), None);
        assert!(super::take_refused().is_some_and(|m| m.contains("not a finite number")));
        assert_eq!(super::take_refused(), None, "said once");
    }

    #[test]
    fn counts_agree_with_their_number() {
        assert_eq!(super::counted(1.0, "cell", "cells"), "1 cell");
        assert_eq!(super::counted(2.0, "cell", "cells"), "2 cells");
        assert_eq!(super::counted(0.5, "cell", "cells"), "0.5 cells");
    }

    #[test]
    fn only_finite_numbers_parse() {
        assert_eq!(super::parse_finite(" 1 234.5 "), Some(1234.5));
        assert_eq!(super::parse_finite("−2"), Some(-2.0));
        assert_eq!(super::parse_finite("6 cells"), Some(6.0));
        assert_eq!(super::parse_finite("12 µm"), Some(12.0));
        for bad in ["nan", "NaN", "inf", "-inf", "abc", ""] {
            assert_eq!(super::parse_finite(bad), None, "{bad}");
        }
    }
}
