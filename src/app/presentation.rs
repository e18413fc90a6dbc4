//! Presentation mode (View ▸ Presentation, Ctrl+Shift+P): for a projector. A light, high-contrast theme
//! (black text on white, heavier strokes), everything drawn 1.2× larger, plot lines twice as
//! thick, and pictures in viridis instead of inferno: a projector crushes inferno's dark end to
//! black, and viridis stays readable under the common colour-vision deficiencies. The
//! advanced workflows (the Optimize and Measured tabs) fold away.
//!
//! The mode lives in the settings; the widgets read it from the context, where [`apply`] puts
//! it, so that nothing is passed down through every panel.

use egui::{Color32, Stroke};

use crate::app::settings::Settings;
use crate::core::figure::Colormap;

/// How much larger everything is drawn.
pub const ZOOM: f32 = 1.2;
/// How much thicker plot lines are.
pub const LINE_SCALE: f32 = 2.0;

fn flag_id() -> egui::Id {
    egui::Id::unique("presentation mode")
}

/// Sets the theme, the zoom and the mode's flag from `settings`.
pub fn apply(ctx: &egui::Context, settings: &Settings) {
    let on = settings.presentation;
    ctx.data_mut(|d| d.insert_temp(flag_id(), on));
    if on {
        ctx.set_visuals(high_contrast());
        ctx.set_zoom_factor(ZOOM);
    } else {
        ctx.set_visuals(if settings.dark {
            egui::Visuals::dark()
        } else {
            egui::Visuals::light()
        });
        ctx.set_zoom_factor(1.0);
    }
}

/// Whether presentation mode is on.
pub fn is_on(ctx: &egui::Context) -> bool {
    ctx.data(|d| d.get_temp::<bool>(flag_id()).unwrap_or(false))
}

/// The colour map a picture is shown in: inferno becomes viridis in presentation mode.
pub fn colormap(on: bool, map: Colormap) -> Colormap {
    match map {
        Colormap::Inferno if on => Colormap::Viridis,
        other => other,
    }
}

/// A plot line's width in presentation mode or not.
pub fn line_width(on: bool, width: f32) -> f32 {
    if on { width * LINE_SCALE } else { width }
}

/// Black on white with heavier strokes: light theme, text forced to black, outlines at 1.5
/// points, selections in a saturated blue.
fn high_contrast() -> egui::Visuals {
    let mut v = egui::Visuals::light();
    v.override_text_color = Some(Color32::BLACK);
    v.panel_fill = Color32::WHITE;
    v.window_fill = Color32::WHITE;
    v.extreme_bg_color = Color32::WHITE;
    v.window_stroke = Stroke::new(1.5, Color32::BLACK);
    for w in [
        &mut v.widgets.noninteractive,
        &mut v.widgets.inactive,
        &mut v.widgets.hovered,
        &mut v.widgets.active,
    ] {
        w.fg_stroke = Stroke::new(1.5, Color32::BLACK);
        w.bg_stroke = Stroke::new(1.5, Color32::from_gray(60));
    }
    v.selection.bg_fill = Color32::from_rgb(0, 90, 200);
    v.selection.stroke = Stroke::new(1.5, Color32::WHITE);
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::figure::relative_luminance;

    #[test]
    fn the_theme_is_black_on_white_with_at_least_aaa_contrast() {
        let v = high_contrast();
        let l = |c: Color32| relative_luminance([c.r().into(), c.g().into(), c.b().into()]);
        let (text, panel) = (l(v.override_text_color.unwrap()), l(v.panel_fill));
        // WCAG contrast ratio (L1 + 0.05) / (L2 + 0.05); 7:1 is AAA.
        assert!((panel + 0.05) / (text + 0.05) >= 7.0);
    }

    #[test]
    fn pictures_switch_to_viridis_and_lines_thicken_only_in_presentation() {
        assert_eq!(colormap(true, Colormap::Inferno), Colormap::Viridis);
        assert_eq!(colormap(false, Colormap::Inferno), Colormap::Inferno);
        assert_eq!(colormap(true, Colormap::Gray), Colormap::Gray);
        assert_eq!(line_width(true, 2.0), 4.0);
        assert_eq!(line_width(false, 2.0), 2.0);
    }
}
