//! A figure panel ([`crate::core::figure::Panel`]) drawn with egui_plot: the same description
//! the files are drawn from (`crate::io::figure`), so a plot on screen and its exported PNG
//! agree, with the studio's tick ladder, hover and zoom.

use std::collections::{BTreeSet, HashMap};
use std::hash::Hash;
use std::sync::Arc;

use egui::{
    Align2, Color32, ColorImage, Mesh, Rect, Sense, Stroke, TextureHandle, TextureId,
    TextureOptions, Ui, pos2, vec2,
};
use egui_plot::{
    Bar, BarChart, FilledArea, HLine, HoverPosition, Legend, Line, LineStyle, MarkerShape, Plot,
    PlotImage, PlotPoint, PlotPoints, PlotUi, Points, VLine,
};

use crate::app::widgets::plot::{LegendEntry, Swatch, hidden_names, legend_ui};
pub use crate::core::figure::short_value;
use crate::core::figure::{
    Annotation, ColorScale, Corner, Image, Mark, Paint, Panel, RING_SEGMENTS, Rgb, circle_points,
    palette,
};

/// The most points a point cloud draws each frame: beyond a few thousand an even sample shows
/// the cloud as well and keeps scrolling smooth (lines are always drawn whole).
const MAX_POINTS_DRAWN: usize = 5000;

/// The egui colour of a palette colour.
pub fn color32(c: Rgb) -> Color32 {
    Color32::from_rgb(c.0, c.1, c.2)
}

/// Draws `panel` (without its title: the caller places it) `height` points tall.
pub fn panel_ui(ui: &mut egui::Ui, id: impl egui::AsIdSalt, panel: &Panel, height: f32) {
    panel_ui_in(ui, id, panel, PlotFrame::tall(height));
}

/// Where a panel's plot sits: its size, and the plots its x axis pans and zooms with.
#[derive(Debug, Clone, Copy)]
pub struct PlotFrame {
    /// Width in points; `None`: the available width.
    pub width: Option<f32>,
    /// Height in points.
    pub height: f32,
    /// Plots sharing this id share their x axis (side-by-side channels).
    pub link_x: Option<egui::Id>,
    /// The legend above the plot, where a click hides or shows a name's series (a plot with
    /// many curves), instead of inside it.
    pub legend_above: bool,
}

impl PlotFrame {
    /// The available width, `height` points tall, on its own.
    pub fn tall(height: f32) -> Self {
        PlotFrame {
            width: None,
            height,
            link_x: None,
            legend_above: false,
        }
    }
}

/// Draws `panel` (without its title) in `frame`.
pub fn panel_ui_in(ui: &mut egui::Ui, id: impl egui::AsIdSalt, panel: &Panel, frame: PlotFrame) {
    panel_plot_ui(ui, id, panel, frame);
}

/// Draws `panel` as [`panel_ui_in`] does and returns the plot's response and its transform
/// (what a caller needs to find the data point under the pointer).
pub fn panel_plot_ui(
    ui: &mut egui::Ui,
    id: impl egui::AsIdSalt,
    panel: &Panel,
    frame: PlotFrame,
) -> (egui::Response, egui_plot::PlotTransform) {
    let height = frame.height;
    let hidden = if frame.legend_above {
        let legend = ui.make_persistent_id((&id, "figure legend"));
        legend_ui(ui, legend, &legend_rows(panel));
        hidden_names(ui.ctx(), legend)
    } else {
        BTreeSet::new()
    };
    let mut plot = Plot::new(id);
    if let Some(w) = frame.width {
        plot = plot.width(w);
    }
    if let Some(link) = frame.link_x {
        plot = plot.link_axis(link, [true, false]);
    }
    if panel.wants_legend() && !frame.legend_above {
        let corner = match panel.quietest_corner() {
            Corner::LeftTop => egui_plot::Corner::LeftTop,
            Corner::LeftBottom => egui_plot::Corner::LeftBottom,
            Corner::RightTop => egui_plot::Corner::RightTop,
            Corner::RightBottom => egui_plot::Corner::RightBottom,
        };
        plot = plot.legend(Legend::default().position(corner));
    }
    // The axis titles after the ticks, which replace the axes.
    let mut plot = crate::app::widgets::plot::with_nice_ticks(plot.height(height))
        .x_axis_label(panel.x.title())
        .y_axis_label(panel.y.title());
    plot = with_axis_words(plot, panel);
    let shown = plot.show(ui, |pl| {
        if hidden.is_empty() {
            series_ui(pl, panel);
        } else {
            let mut shown = panel.clone();
            shown.series.retain(|s| !hidden.contains(&s.name));
            series_ui(pl, &shown);
        }
        annotations_ui(pl, panel, true);
    });
    save_menu(&shown.response, panel);
    (shown.response, shown.transform)
}

/// A figure that a plot's context menu asked to save: the app takes it, adds the caption of
/// the document it shows and asks for the format, size and file ([`take_save_request`]).
#[derive(Clone, Default)]
pub struct SaveRequest(pub Arc<Panel>);

fn save_request_id() -> egui::Id {
    egui::Id::unique("save figure request")
}

/// Offers "Save figure…" in the context menu (right click) of the plot `response` drew.
pub fn save_menu(response: &egui::Response, panel: &Panel) {
    response.context_menu(|ui| {
        if ui.button("Save figure…").clicked() {
            request_save(ui.ctx(), panel);
            ui.close();
        }
    });
}

/// Asks the app to save `panel` as a figure (a view's Save figure button, the context menu).
pub fn request_save(ctx: &egui::Context, panel: &Panel) {
    let request = SaveRequest(Arc::new(panel.clone()));
    ctx.data_mut(|d| d.insert_temp(save_request_id(), request));
}

/// The figure asked to be saved since the last call, if any.
pub fn take_save_request(ctx: &egui::Context) -> Option<SaveRequest> {
    ctx.data_mut(|d| d.remove_temp::<SaveRequest>(save_request_id()))
}

/// The legend's rows (the panel's, or one row of every name), one entry a series name with
/// its first series' colour and mark.
fn legend_rows(panel: &Panel) -> Vec<Vec<LegendEntry>> {
    let entry = |name: &str| {
        let s = panel.series.iter().find(|s| s.name == name)?;
        let c = color32(s.colour);
        let (colour, swatch) = match s.mark {
            Mark::Line => (c, Swatch::Solid(2)),
            Mark::FaintLine => (c.gamma_multiply(0.55), Swatch::Solid(1)),
            Mark::DashedLine => (c, Swatch::Dashed),
            Mark::DottedLine => (c, Swatch::Dotted),
            Mark::Rules => (c.gamma_multiply(0.6), Swatch::Dotted),
            Mark::Bars => (c, Swatch::Solid(4)),
            Mark::Points | Mark::LineAndPoints | Mark::Hollow => (c, Swatch::Marker),
        };
        Some(LegendEntry::new(name, colour, swatch))
    };
    if panel.legend_rows.is_empty() {
        let mut names: Vec<&str> = Vec::new();
        for s in &panel.series {
            if !names.contains(&s.name.as_str()) {
                names.push(&s.name);
            }
        }
        vec![names.into_iter().filter_map(entry).collect()]
    } else {
        panel
            .legend_rows
            .iter()
            .map(|row| row.iter().filter_map(|n| entry(n)).collect())
            .collect()
    }
}

/// Tick labels the axes need besides numbers (a word axis's names, a log axis's powers of
/// ten, a downward axis's magnitudes) and the range each opens on.
fn with_axis_words<'a>(mut plot: Plot<'a>, panel: &Panel) -> Plot<'a> {
    if panel.x.categories.is_some() {
        // A word axis (a tiling): its values sit at 0, 1, 2… and are named there.
        let axis = panel.x.clone();
        plot =
            plot.x_axis_formatter(move |mark, _| axis.category_at(mark.value).unwrap_or_default());
    } else if panel.x.log10 || panel.x.downward {
        let axis = panel.x.clone();
        plot =
            plot.x_axis_formatter(move |mark, _| axis.tick_label(mark.value).unwrap_or_default());
    }
    if panel.y.log10 || panel.y.downward {
        let axis = panel.y.clone();
        plot =
            plot.y_axis_formatter(move |mark, _| axis.tick_label(mark.value).unwrap_or_default());
    }
    if let Some(ticks) = panel.x.ticks.clone() {
        plot = plot.x_grid_spacer(move |_| {
            ticks
                .iter()
                .map(|v| egui_plot::GridMark {
                    value: *v,
                    step_size: 1.0,
                })
                .collect()
        });
    }
    if let Some([lo, hi]) = panel.x.view {
        plot = plot.default_x_bounds(lo, hi);
    }
    if let Some([lo, hi]) = panel.y.view {
        plot = plot.default_y_bounds(lo, hi);
    }
    plot
}

/// The panel's series, in order.
fn series_ui(pl: &mut PlotUi<'_>, panel: &Panel) {
    let bar_width = panel.bar_width();
    let on = crate::app::presentation::is_on(pl.ctx());
    let w = |width: f32| crate::app::presentation::line_width(on, width);
    for s in &panel.series {
        let c = color32(s.colour);
        if let Some(band) = &s.band {
            let xs: Vec<f64> = band.iter().map(|b| b[0]).collect();
            let lo: Vec<f64> = band.iter().map(|b| b[1]).collect();
            let hi: Vec<f64> = band.iter().map(|b| b[2]).collect();
            pl.add(
                FilledArea::new(format!("{} ± SD", s.name), &xs, &lo, &hi)
                    .fill_color(c.gamma_multiply(0.25)),
            );
        }
        let finite = |p: &&[f64; 2]| p[0].is_finite() && p[1].is_finite();
        match s.mark {
            Mark::Points => {
                let step = s.points.len().div_ceil(MAX_POINTS_DRAWN).max(1);
                let name = if step > 1 {
                    format!("{} (1 in {step})", s.name)
                } else {
                    s.name.clone()
                };
                let cloud: PlotPoints = s
                    .points
                    .iter()
                    .step_by(step)
                    .filter(finite)
                    .copied()
                    .collect();
                pl.points(Points::new(name, cloud).color(c).radius(3.0));
            }
            Mark::FaintLine | Mark::DottedLine => {
                let line: Vec<[f64; 2]> = s.points.iter().filter(finite).copied().collect();
                let l = Line::new(s.name.clone(), PlotPoints::from(line));
                pl.line(if s.mark == Mark::FaintLine {
                    l.color(c.gamma_multiply(0.55)).width(w(1.0))
                } else {
                    l.color(c)
                        .width(w(1.5))
                        .style(LineStyle::Dotted { spacing: 4.0 })
                });
            }
            Mark::Rules => {
                for p in s.points.iter().filter(finite) {
                    pl.vline(
                        VLine::new(s.name.clone(), p[0])
                            .color(c.gamma_multiply(0.6))
                            .style(LineStyle::dotted_dense())
                            .allow_hover(false),
                    );
                }
            }
            Mark::Hollow => {
                let at: PlotPoints = s.points.iter().filter(finite).copied().collect();
                pl.points(
                    Points::new(s.name.clone(), at)
                        .color(c)
                        .shape(MarkerShape::Diamond)
                        .filled(false)
                        .radius(6.0),
                );
            }
            Mark::Bars => {
                let bars = s
                    .points
                    .iter()
                    .filter(finite)
                    .map(|p| Bar::new(p[0], p[1]).width(bar_width).fill(c))
                    .collect();
                pl.bar_chart(BarChart::new(s.name.clone(), bars).color(c));
            }
            Mark::DashedLine => {
                let line: Vec<[f64; 2]> = s.points.iter().filter(finite).copied().collect();
                // A reference is read against the data, not over it: dimmer.
                let l = Line::new(s.name.clone(), PlotPoints::from(line))
                    .color(c.gamma_multiply(0.6))
                    .style(LineStyle::dashed_dense());
                // egui_plot's own width unless presenting.
                pl.line(if on { l.width(w(1.5)) } else { l });
            }
            Mark::Line | Mark::LineAndPoints => {
                let line: Vec<[f64; 2]> = s.points.iter().filter(finite).copied().collect();
                let dots = (s.mark == Mark::LineAndPoints).then(|| line.clone());
                pl.line(
                    Line::new(s.name.clone(), PlotPoints::from(line))
                        .color(c)
                        .width(w(2.0)),
                );
                if let Some(dots) = dots {
                    pl.points(
                        Points::new(s.name.clone(), PlotPoints::from(dots))
                            .color(c)
                            .radius(3.0),
                    );
                }
            }
        }
    }
}

/// The panel's annotations in the annotation colour; `hover`: whether the pointer reads them
/// (over an image it must keep reading the image).
fn annotations_ui(pl: &mut PlotUi<'_>, panel: &Panel, hover: bool) {
    let c = color32(palette::ANNOTATION);
    for a in &panel.annotations {
        match a {
            Annotation::Ring {
                centre,
                radius,
                label,
            } => {
                let ring: PlotPoints = circle_points(*centre, *radius, RING_SEGMENTS).into();
                pl.line(
                    Line::new(label.clone(), ring)
                        .color(c)
                        .width(1.5)
                        .allow_hover(hover),
                );
            }
            Annotation::Lattice { points, label } => {
                let lattice: PlotPoints = points.iter().copied().collect();
                pl.points(
                    Points::new(label.clone(), lattice)
                        .shape(MarkerShape::Plus)
                        .color(c)
                        .radius(3.0)
                        .allow_hover(hover),
                );
            }
            Annotation::VLine { x, label } => {
                pl.vline(VLine::new(label.clone(), *x).color(c).allow_hover(hover));
            }
            Annotation::HLine { y, label } => {
                pl.hline(HLine::new(label.clone(), *y).color(c).allow_hover(hover));
            }
        }
    }
}

/// Where an image panel sits: its size, the plots it pans, zooms and hovers with, and the view
/// it opens on (and returns to on a double-click).
#[derive(Debug, Clone, Copy)]
pub struct ImageFrame {
    /// Width and height of the plot widget, axes included.
    pub size: egui::Vec2,
    /// Plots sharing this id pan, zoom and hover together.
    pub link: Option<egui::Id>,
    /// Half-width of the square about the origin the plot opens on; `None`: the whole image.
    pub view_half: Option<f64>,
}

/// The view an image panel opens on: where its first image is brighter than its colour scale's
/// floor, when that image is light mapped about the origin (a PSF, an MTF); `None`, the whole
/// picture, for anything else (a photo or a map in pixels).
pub fn lit_view_half(panel: &Panel) -> Option<f64> {
    let img = panel.images.first()?;
    let [w, h] = img.cell();
    let centred = img.centre[0].abs() <= w && img.centre[1].abs() <= h;
    let light = matches!(img.paint, Paint::Mapped | Paint::Composite(_));
    (centred && light).then(|| img.lit_half_extent(img.scale.visible_threshold()))
}

/// Draws an image `panel` (without its title) with `textures` for its images, in order, and a
/// readout of the first image's value under the pointer.
pub fn image_panel_ui(
    ui: &mut Ui,
    id: impl egui::AsIdSalt,
    panel: &Panel,
    textures: &[TextureId],
    frame: ImageFrame,
) {
    let x_unit = panel.x.unit.clone().unwrap_or_default();
    let y_unit = panel.y.unit.clone().unwrap_or_default();
    let y_axis = panel.y.clone();
    let first = panel.images.first().cloned();
    let readout = move |pos: &HoverPosition<'_>| {
        let at = match pos {
            HoverPosition::NearDataPoint { position, .. }
            | HoverPosition::Elsewhere { position } => *position,
        };
        let img = first.as_ref()?;
        let [row, col] = img.index_at(at.x, at.y)?;
        let v = *img.values.get([row, col])?;
        let [x, y] = img.position(row, col);
        let y = y_axis.shown(y);
        Some(format!(
            "x = {} {x_unit}, y = {} {y_unit}\n{}",
            coordinate(x),
            coordinate(y),
            value_readout(img, v)
        ))
    };
    let mut plot = crate::app::widgets::plot::with_nice_ticks(Plot::new(id))
        .width(frame.size.x)
        .height(frame.size.y)
        .show_crosshair(false)
        .x_axis_label(panel.x.title())
        .y_axis_label(panel.y.title())
        .label_formatter(readout);
    plot = with_axis_words(plot, panel);
    if panel.equal_aspect {
        plot = plot.data_aspect(1.0);
    }
    if let Some(half) = frame.view_half {
        plot = plot
            .default_x_bounds(-half, half)
            .default_y_bounds(-half, half);
    }
    if let Some(link) = frame.link {
        plot = plot.link_axis(link, true).link_cursor(link, true);
    }
    let shown = plot.show(ui, |pl| {
        for (img, texture) in panel.images.iter().zip(textures) {
            // No name: an image needs no legend entry.
            pl.image(PlotImage::new(
                "",
                *texture,
                PlotPoint::new(img.centre[0], img.centre[1]),
                vec2(img.size[0] as f32, img.size[1] as f32),
            ));
        }
        series_ui(pl, panel);
        // No legend over the data: the controls above the plot name the annotations.
        annotations_ui(pl, panel, false);
    });
    // A screen reader (and a test) finds the picture by its title.
    let title = panel.title.clone();
    shown
        .response
        .widget_info(|| egui::WidgetInfo::labeled(egui::Role::Image, true, &title));
    save_menu(&shown.response, panel);
}

/// A position in the readout: whole numbers past a thousand (pixel 1324, not 1.32e3), else
/// about three digits.
fn coordinate(v: f64) -> String {
    if (1000.0..1e7).contains(&v.abs()) {
        format!("{v:.0}")
    } else {
        short_value(v)
    }
}

/// The value under the pointer as the readout shows it: its true value (or category), and
/// where a log scale draws it (a value below the floor is drawn at the floor).
fn value_readout(img: &Image, v: f64) -> String {
    let mapped = matches!(img.paint, Paint::Mapped);
    let log = match img.scale {
        ColorScale::Log { reference, .. } if mapped && v > 0.0 && reference > 0.0 => {
            format!(
                "\nlog10({} / peak) = {:.2}",
                img.name,
                (v / reference).log10()
            )
        }
        ColorScale::Log { .. } if mapped => "\n(no light: drawn at the floor)".to_owned(),
        ColorScale::Linear { .. } if mapped && v > 0.0 => format!("\nlog10 = {:.2}", v.log10()),
        _ => String::new(),
    };
    format!("{}{log}", img.describe(v))
}

/// Width reserved beside an image panel for its colour bar and tick labels.
pub const COLORBAR_WIDTH: f32 = 78.0;

/// The colour bar of `img`, `height` points tall: its map bottom to top with the scale's ticks
/// (a log scale's as decades below the peak); a categorical image's key instead; nothing (the
/// space kept) for a picture drawn as it is seen. Drawn as a mesh each frame (a few dozen
/// quads: cheaper than keeping a texture).
pub fn colour_bar_ui(ui: &mut Ui, height: f32, img: &Image) {
    let (rect, response) = ui.allocate_exact_size(vec2(COLORBAR_WIDTH, height), Sense::hover());
    // A screen reader (and a test) reads the bar's or the key's words.
    let words = match &img.paint {
        Paint::Categories(cats) => {
            let labels: Vec<&str> = cats.iter().map(|c| c.label.as_str()).collect();
            format!("key of {}: {}", img.name, labels.join(", "))
        }
        _ => {
            let ticks: Vec<String> = img
                .scale
                .tick_labels()
                .into_iter()
                .map(|(_, l)| l)
                .collect();
            format!("colour bar of {}: {}", img.name, ticks.join(", "))
        }
    };
    if img.paint.has_colour_bar() || matches!(img.paint, Paint::Categories(_)) {
        response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Image, true, &words));
    }
    let painter = ui.painter_at(rect);
    let text = ui.visuals().text_color();
    let font = egui::TextStyle::Body.resolve(ui.style());
    if let Paint::Categories(cats) = &img.paint {
        for (k, cat) in cats.iter().enumerate() {
            let top = rect.top() + 8.0 + 20.0 * k as f32;
            let swatch = Rect::from_min_size(pos2(rect.left() + 4.0, top), vec2(14.0, 14.0));
            painter.rect_filled(swatch, 2.0, color32(cat.colour));
            painter.text(
                pos2(swatch.right() + 6.0, swatch.center().y),
                Align2::LEFT_CENTER,
                &cat.label,
                font.clone(),
                text,
            );
        }
        return;
    }
    if !img.paint.has_colour_bar() {
        return;
    }
    let bar = Rect::from_min_max(
        pos2(rect.left() + 4.0, rect.top() + 8.0),
        pos2(rect.left() + 18.0, rect.bottom() - 8.0),
    );
    const BANDS: usize = 64;
    let on = crate::app::presentation::is_on(ui.ctx());
    let map = crate::app::presentation::colormap(on, img.colormap);
    let mut mesh = Mesh::default();
    for k in 0..BANDS {
        let t0 = k as f32 / BANDS as f32;
        let t1 = (k + 1) as f32 / BANDS as f32;
        let band = Rect::from_min_max(
            pos2(bar.left(), bar.bottom() - t1 * bar.height()),
            pos2(bar.right(), bar.bottom() - t0 * bar.height()),
        );
        mesh.add_colored_rect(band, color32(map.at((t0 + t1) / 2.0)));
    }
    painter.add(mesh);
    painter.rect_stroke(
        bar,
        0.0,
        Stroke::new(1.0, ui.visuals().weak_text_color()),
        egui::StrokeKind::Outside,
    );
    for (t, label) in img.scale.tick_labels() {
        let y = bar.bottom() - t * bar.height();
        painter.line_segment(
            [pos2(bar.right(), y), pos2(bar.right() + 4.0, y)],
            Stroke::new(1.0, text),
        );
        painter.text(
            pos2(bar.right() + 6.0, y),
            Align2::LEFT_CENTER,
            label,
            font.clone(),
            text,
        );
    }
}

/// The textures of `panel`'s images, in order, named `name/0`, `name/1`…
pub fn panel_textures(ctx: &egui::Context, name: &str, panel: &Panel) -> Vec<TextureHandle> {
    panel
        .images
        .iter()
        .enumerate()
        .map(|(i, img)| image_texture(ctx, format!("{name}/{i}"), img))
        .collect()
}

/// The texture of `img`: its colours as an egui image (nearest sampling: every sample stays a
/// crisp square when zoomed in).
pub fn image_texture(ctx: &egui::Context, name: String, img: &Image) -> TextureHandle {
    let (rows, cols) = img.values.dim();
    let shown = Image {
        colormap: crate::app::presentation::colormap(
            crate::app::presentation::is_on(ctx),
            img.colormap,
        ),
        ..img.clone()
    };
    let rgb: Vec<u8> = shown
        .colours()
        .into_iter()
        .flat_map(|c| [c.0, c.1, c.2])
        .collect();
    ctx.load_texture(
        name,
        ColorImage::from_rgb([cols, rows], &rgb),
        TextureOptions::NEAREST,
    )
}

/// A figure as a view draws it: the panel, its images' textures in order, and the view it
/// opens on (worked out once, with the textures, not every frame).
#[derive(Clone)]
pub struct Shown {
    /// The panel.
    pub panel: Arc<Panel>,
    /// Its images' textures, in order.
    pub textures: Vec<TextureId>,
    /// Half-width of the square it opens on: where its first image is lit ([`lit_view_half`]).
    pub view_half: Option<f64>,
}

/// Figure panels built once per key, their images uploaded as textures: a view asks for its
/// slot's panel every frame and gets the built one back until its key changes.
pub struct FigureCache<S, K> {
    slots: HashMap<S, (K, Built)>,
    /// Panels built so far (lets tests prove nothing is rebuilt per frame).
    builds: u64,
}

/// A slot's built figure: the panel, its uploaded textures and the view it opens on.
struct Built {
    panel: Arc<Panel>,
    textures: Vec<TextureHandle>,
    view_half: Option<f64>,
    /// Built in presentation mode.
    presentation: bool,
}

impl<S, K> Default for FigureCache<S, K> {
    fn default() -> Self {
        FigureCache {
            slots: HashMap::new(),
            builds: 0,
        }
    }
}

impl<S: Hash + Eq + Copy + std::fmt::Debug, K: PartialEq> FigureCache<S, K> {
    /// The panel of `slot` for `key` with its images' textures: `build` runs (and the images
    /// are uploaded) only when the slot is empty or holds another key.
    pub fn get(
        &mut self,
        ctx: &egui::Context,
        slot: S,
        key: K,
        build: impl FnOnce() -> Panel,
    ) -> Shown {
        // Presentation mode draws pictures in another colour map: its textures are rebuilt.
        let on = crate::app::presentation::is_on(ctx);
        let fresh =
            !matches!(self.slots.get(&slot), Some((k, b)) if *k == key && b.presentation == on);
        if fresh {
            self.builds += 1;
            let panel = Arc::new(build());
            let textures = panel_textures(ctx, &format!("figure/{slot:?}"), &panel);
            let view_half = lit_view_half(&panel);
            let built = Built {
                panel,
                textures,
                view_half,
                presentation: on,
            };
            self.slots.insert(slot, (key, built));
        }
        match self.slots.get(&slot) {
            Some((_, b)) => Shown {
                panel: b.panel.clone(),
                textures: b.textures.iter().map(TextureHandle::id).collect(),
                view_half: b.view_half,
            },
            None => Shown {
                panel: Arc::new(Panel::default()),
                textures: Vec::new(),
                view_half: None,
            },
        }
    }

    /// Panels built so far.
    pub fn builds(&self) -> u64 {
        self.builds
    }
}
