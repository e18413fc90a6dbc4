//! Widgets every workspace uses and none owns: colour maps, photos, the message line.

pub mod colormap;
pub mod photo;

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

/// egui's own number syntax (spaces ignored, `−` as minus), finite values only.
fn parse_finite(text: &str) -> Option<f64> {
    let cleaned: String = text
        .chars()
        .filter(|c| !c.is_whitespace())
        .map(|c| if c == '−' { '-' } else { c })
        .collect();
    cleaned.parse::<f64>().ok().filter(|v| v.is_finite())
}

#[cfg(test)]
mod tests {
    #[test]
    fn only_finite_numbers_parse() {
        assert_eq!(super::parse_finite(" 1 234.5 "), Some(1234.5));
        assert_eq!(super::parse_finite("−2"), Some(-2.0));
        for bad in ["nan", "NaN", "inf", "-inf", "abc", ""] {
            assert_eq!(super::parse_finite(bad), None, "{bad}");
        }
    }
}
