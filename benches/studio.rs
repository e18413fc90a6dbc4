//! Studio latency: frame time while dragging on the editor, and the time from a committed edit
//! to the first result on screen and to the full-quality result (through the real worker
//! thread). The first result is a preview where the design's f-number allows one that agrees
//! with full quality (the `f10` case), the full-quality result itself at the thesis's f/2.5.

use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use egui_kittest::Harness;
use udc_studio::app::{
    AppDirs, DisplayAction, DisplayWorkspace, Payload, StudioApp, StudioOptions, Worker,
};
use udc_studio::core::Design;
use udc_studio::core::analysis::analyze::Quality;

fn harness() -> Harness<'static, StudioApp> {
    Harness::builder()
        .with_size(egui::vec2(1440.0, 900.0))
        .build_eframe(|cc| {
            StudioApp::new(
                &cc.egui_ctx,
                StudioOptions {
                    dirs: AppDirs::none(),
                    design_path: None,
                    native_dialogs: false,
                    autosave_every: Duration::from_secs(3600),
                    gpu: None,
                },
            )
        })
}

fn frame_while_dragging(c: &mut Criterion) {
    let mut h = harness();
    h.state_mut()
        .ws_with_shell(|ws: &mut DisplayWorkspace, shell| {
            ws.act(DisplayAction::LoadPreset("toled-150dpi".into()), shell);
        });
    let start = Instant::now();
    while !h.state().ws::<DisplayWorkspace>().is_up_to_date()
        && start.elapsed() < Duration::from_secs(30)
    {
        h.step();
        std::thread::sleep(Duration::from_millis(5));
    }
    h.step();
    let Some(rect) = h.state().ws::<DisplayWorkspace>().editor().grid_rect() else {
        eprintln!("editor not drawn; skipping");
        return;
    };
    let a = rect.left_top() + rect.size() * 0.1;
    h.hover_at(a);
    h.step();
    h.event(egui::Event::PointerButton {
        pos: a,
        button: egui::PointerButton::Primary,
        pressed: true,
        modifiers: Default::default(),
    });
    h.step();
    let mut k = 0u32;
    c.bench_function("studio/frame-while-dragging", |b| {
        b.iter(|| {
            k = (k + 1) % 200;
            let t = k as f32 / 200.0;
            h.event(egui::Event::PointerMoved(
                rect.left_top() + rect.size() * (0.1 + 0.8 * t),
            ));
            h.step();
        })
    });
}

/// Submits a new design and waits for its first result of the wanted quality (`None`: of any).
fn edit_to(worker: &mut Worker, design: &Design, quality: Option<Quality>) -> Duration {
    let t = Instant::now();
    let generation = worker.submit(design.clone());
    loop {
        let Some(r) = worker.wait(Duration::from_secs(30)) else {
            return t.elapsed();
        };
        if r.generation == generation
            && let Payload::Analysis { quality: q, .. } = r.payload
            && quality.is_none_or(|want| want == q)
        {
            return t.elapsed();
        }
    }
}

/// Designs that differ from `base` in one cell each time: every job is a genuinely new design.
fn variants(base: Design) -> impl FnMut() -> Design {
    let mut seed = 0u64;
    move || {
        let mut d = base.clone();
        seed += 1;
        d.opening.cells[0][(seed % 21) as usize] = 1.0;
        d
    }
}

fn edit_latency(c: &mut Criterion) {
    let compute = udc_studio::app::compute::Compute::new(None, Default::default());
    let mut worker = Worker::spawn(|| {}, compute.shared());
    let mut slow = Design::default_toled();
    slow.optics.f_number = 10.0;
    let mut g = c.benchmark_group("studio/edit-to");
    g.sample_size(20);
    for (id, base, quality) in [
        ("first", Design::default_toled(), None),
        ("full", Design::default_toled(), Some(Quality::Full)),
        ("first/f10", slow.clone(), None),
        ("full/f10", slow, Some(Quality::Full)),
    ] {
        let mut variant = variants(base);
        edit_to(&mut worker, &variant(), Some(Quality::Full));
        g.bench_function(id, |b| {
            b.iter_custom(|iters| {
                (0..iters)
                    .map(|_| edit_to(&mut worker, &variant(), quality))
                    .sum()
            })
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(4));
    targets = frame_while_dragging, edit_latency
}
criterion_main!(benches);
