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
